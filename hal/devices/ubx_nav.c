/* UBX NAV payloads of a u-blox 6 (GPS.G6-SW-10018, "UBX Class NAV") from one epoch's solution. */
#include "ubx_nav.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)
#define WGS84_A 6378137.0 /* NIMA TR8350.2 table 3.1 */
#define WGS84_F (1.0 / 298.257223563)
#define WEEK_MS INT64_C(604800000)

/* Flags as the specification numbers them. */
#define FIX_NONE 0x00
#define FIX_3D 0x03
#define SOL_FIX_OK 0x01 /* NAV-SOL flags and NAV-STATUS flags: gpsFixOk */
#define SOL_WKN_SET 0x04
#define SOL_TOW_SET 0x08
#define TIME_TOW_VALID 0x01 /* NAV-TIMEGPS valid; NAV-TIMEUTC: validTOW */
#define TIME_WEEK_VALID 0x02
#define TIME_LEAP_VALID 0x04 /* NAV-TIMEGPS leapS; NAV-TIMEUTC: validUTC */
#define SV_USED 0x01
#define SV_ORBIT_AVAIL 0x04
#define SV_ORBIT_EPH 0x08
#define QUALITY_CODE_LOCK 4     /* code locked and time synchronised */
#define QUALITY_CARRIER_LOCK 7  /* code and carrier locked: what a satellite in the solution shows */
#define CHIP_GEN_UBLOX6 2       /* NAV-SVINFO globalFlags chipGen */
#define SBAS_SYS_UNKNOWN (-1)
#define UNKNOWN_ACCURACY 0xFFFFFFFFu /* before a fix the estimates have no bound */

static const uint8_t ids[UBX_NAV_MSGS] = {0x01, 0x02, 0x03, 0x04, 0x06, 0x11, 0x12, 0x20, 0x21, 0x30, 0x32};

uint8_t ubx_nav_id(enum ubx_nav_msg m) { return ids[m]; }

int ubx_nav_index(uint8_t id) {
  for (int i = 0; i < UBX_NAV_MSGS; ++i)
    if (ids[i] == id) return i;
  return -1;
}

void ubx_gps_time(int64_t utc_ms, int16_t *week, uint32_t *itow_ms) {
  const int64_t gps_ms = utc_ms - UBX_GPS_EPOCH_UNIX_S * 1000 + UBX_LEAP_SECONDS * 1000;
  int64_t w = gps_ms / WEEK_MS, tow = gps_ms % WEEK_MS;
  if (tow < 0) {
    tow += WEEK_MS;
    --w;
  }
  *week = (int16_t)w;
  *itow_ms = (uint32_t)tow;
}

void ubx_ecef(double latitude_deg, double longitude_deg, double height_m, double xyz[3]) {
  const double e2 = WGS84_F * (2.0 - WGS84_F);
  const double sl = sin(latitude_deg * DEG), cl = cos(latitude_deg * DEG);
  const double n = WGS84_A / sqrt(1.0 - e2 * sl * sl); /* prime vertical radius of curvature */
  xyz[0] = (n + height_m) * cl * cos(longitude_deg * DEG);
  xyz[1] = (n + height_m) * cl * sin(longitude_deg * DEG);
  xyz[2] = (n * (1.0 - e2) + height_m) * sl;
}

void ubx_enu_to_ecef(double latitude_deg, double longitude_deg, double e, double n, double u, double xyz[3]) {
  const double sl = sin(latitude_deg * DEG), cl = cos(latitude_deg * DEG);
  const double so = sin(longitude_deg * DEG), co = cos(longitude_deg * DEG);
  xyz[0] = -so * e - sl * co * n + cl * co * u;
  xyz[1] = co * e - sl * so * n + cl * so * u;
  xyz[2] = cl * n + sl * u;
}

int ubx_dops(const struct nmea_solution *f, struct ubx_dop_set *d) {
  double a[4][4] = {{0}};
  int count = 0;
  for (int k = 0; k < f->used_count; ++k)
    for (int i = 0; i < f->in_view; ++i) {
      if (f->sky[i].prn != f->used_prn[k] || f->sky[i].elevation_deg < 0) continue;
      const double el = f->sky[i].elevation_deg * DEG, az = f->sky[i].azimuth_deg * DEG;
      const double g[4] = {cos(el) * sin(az), cos(el) * cos(az), sin(el), 1.0}; /* e, n, u, clock */
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) a[r][c] += g[r] * g[c];
      ++count;
    }
  if (count < 4) return 0;
  /* A = L L^T; the diagonal of A^-1 is the squared norms of the columns of L^-1. */
  double l[4][4] = {{0}};
  for (int j = 0; j < 4; ++j) {
    double s = a[j][j];
    for (int k = 0; k < j; ++k) s -= l[j][k] * l[j][k];
    if (!(s > 1e-12)) return 0;
    l[j][j] = sqrt(s);
    for (int i = j + 1; i < 4; ++i) {
      double t = a[i][j];
      for (int k = 0; k < j; ++k) t -= l[i][k] * l[j][k];
      l[i][j] = t / l[j][j];
    }
  }
  double q[4] = {0};
  for (int c = 0; c < 4; ++c) { /* column c of L^-1 by forward substitution */
    double x[4] = {0};
    for (int i = c; i < 4; ++i) {
      double s = i == c ? 1.0 : 0.0;
      for (int k = c; k < i; ++k) s -= l[i][k] * x[k];
      x[i] = s / l[i][i];
    }
    for (int i = c; i < 4; ++i) q[c] += x[i] * x[i];
  }
  d->e = sqrt(q[0]);
  d->n = sqrt(q[1]);
  d->v = sqrt(q[2]);
  d->t = sqrt(q[3]);
  d->h = sqrt(q[0] + q[1]);
  d->p = sqrt(q[0] + q[1] + q[2]);
  d->g = sqrt(q[0] + q[1] + q[2] + q[3]);
  return 1;
}

/* ---- little-endian fields ---- */

static void u1(uint8_t *p, unsigned v) { p[0] = (uint8_t)(v & 0xFF); }
static void u2(uint8_t *p, unsigned v) {
  p[0] = (uint8_t)(v & 0xFF);
  p[1] = (uint8_t)(v >> 8 & 0xFF);
}
static void u4(uint8_t *p, uint32_t v) {
  u2(p, v & 0xFFFF);
  u2(p + 2, v >> 16);
}
static void i4(uint8_t *p, int32_t v) { u4(p, (uint32_t)v); }

/* A value in the field's unit, rounded; clamped to the field's range. */
static int32_t scaled_i4(double v, double per_unit) {
  const double x = nearbyint(v * per_unit);
  if (!(x > -2147483648.0)) return INT32_MIN;
  if (x > 2147483647.0) return INT32_MAX;
  return (int32_t)x;
}
static uint32_t scaled_u4(double v, double per_unit) {
  const double x = nearbyint(v * per_unit);
  if (!(x > 0.0)) return 0;
  if (x >= 4294967295.0) return UINT32_MAX;
  return (uint32_t)x;
}
static unsigned dop_u2(double dop) { /* 0.01 units, 99.99 when there is none */
  const double x = nearbyint(dop * 100.0);
  return x > 0.0 && x < 9999.0 ? (unsigned)x : 9999u;
}

static double height_m(const struct nmea_solution *f) { return f->altitude_msl_m + f->geoid_separation_m; }
static uint32_t acc(const struct ubx_epoch *e, double m, double per_unit) {
  return e->fix.valid ? scaled_u4(m, per_unit) : UNKNOWN_ACCURACY;
}
static double p_acc_m(const struct ubx_epoch *e) { return hypot(e->h_acc_m, e->v_acc_m); }

static unsigned time_flags(const struct ubx_epoch *e) {
  return e->fix.time_valid ? SOL_WKN_SET | SOL_TOW_SET : 0u;
}

/* ecefX, ecefY, ecefZ (cm) and pAcc (cm): the same 16 bytes in NAV-POSECEF and NAV-SOL. */
static void ecef_position(const struct ubx_epoch *e, uint8_t *p) {
  double x[3] = {0, 0, 0};
  if (e->fix.valid) ubx_ecef(e->fix.latitude_deg, e->fix.longitude_deg, height_m(&e->fix), x);
  for (int k = 0; k < 3; ++k) i4(p + 4 * k, scaled_i4(x[k], 100.0));
  u4(p + 12, acc(e, p_acc_m(e), 100.0));
}

static uint16_t posecef(const struct ubx_epoch *e, uint8_t *p) {
  u4(p, e->itow_ms);
  ecef_position(e, p + 4);
  return 20;
}

static uint16_t posllh(const struct ubx_epoch *e, uint8_t *p) {
  const struct nmea_solution *f = &e->fix;
  const int v = f->valid;
  u4(p, e->itow_ms);
  i4(p + 4, v ? scaled_i4(f->longitude_deg, 1e7) : 0);
  i4(p + 8, v ? scaled_i4(f->latitude_deg, 1e7) : 0);
  i4(p + 12, v ? scaled_i4(height_m(f), 1e3) : 0);
  i4(p + 16, v ? scaled_i4(f->altitude_msl_m, 1e3) : 0);
  u4(p + 20, acc(e, e->h_acc_m, 1e3));
  u4(p + 24, acc(e, e->v_acc_m, 1e3));
  return 28;
}

static uint16_t status(const struct ubx_epoch *e, uint8_t *p) {
  memset(p, 0, 16);
  u4(p, e->itow_ms);
  u1(p + 4, e->fix.valid ? FIX_3D : FIX_NONE);
  u1(p + 5, (e->fix.valid ? SOL_FIX_OK : 0u) | time_flags(e));
  /* fixStat 0 (no DGPS, no map matching), flags2 0 (power save off: acquisition/tracking) */
  u4(p + 8, e->ttff_ms);
  u4(p + 12, e->msss);
  return 16;
}

static uint16_t dop(const struct ubx_epoch *e, uint8_t *p) {
  struct ubx_dop_set d = {99.99, 99.99, 99.99, 99.99, 99.99, 99.99, 99.99};
  if (e->fix.valid && ubx_dops(&e->fix, &d)) {
    /* The three the NMEA sentences print come from the solution itself, so both agree. */
    d.p = e->fix.pdop;
    d.h = e->fix.hdop;
    d.v = e->fix.vdop;
  }
  u4(p, e->itow_ms);
  const double order[7] = {d.g, d.p, d.t, d.v, d.h, d.n, d.e};
  for (int k = 0; k < 7; ++k) u2(p + 4 + 2 * k, dop_u2(order[k]));
  return 18;
}

static void velocity_ecef(const struct ubx_epoch *e, double v[3]) {
  const struct nmea_solution *f = &e->fix;
  v[0] = v[1] = v[2] = 0.0;
  if (f->valid) ubx_enu_to_ecef(f->latitude_deg, f->longitude_deg, f->east_mps, f->north_mps, f->up_mps, v);
}

static uint16_t sol(const struct ubx_epoch *e, uint8_t *p) {
  memset(p, 0, 52);
  const struct nmea_solution *f = &e->fix;
  u4(p, e->itow_ms);
  i4(p + 4, 0); /* fTOW: epochs fall on whole milliseconds of the receiver's (exact) clock */
  u2(p + 8, f->time_valid ? (uint16_t)e->week : 0u);
  u1(p + 10, f->valid ? FIX_3D : FIX_NONE);
  u1(p + 11, (f->valid ? SOL_FIX_OK : 0u) | time_flags(e));
  ecef_position(e, p + 12);
  double v[3];
  velocity_ecef(e, v);
  for (int k = 0; k < 3; ++k) i4(p + 28 + 4 * k, scaled_i4(v[k], 100.0));
  u4(p + 40, acc(e, e->s_acc_mps, 100.0));
  u2(p + 44, dop_u2(f->valid ? f->pdop : 99.99));
  u1(p + 47, f->valid ? (unsigned)f->used_count : 0u);
  return 52;
}

static uint16_t velecef(const struct ubx_epoch *e, uint8_t *p) {
  double v[3];
  velocity_ecef(e, v);
  u4(p, e->itow_ms);
  for (int k = 0; k < 3; ++k) i4(p + 4 + 4 * k, scaled_i4(v[k], 100.0));
  u4(p + 16, acc(e, e->s_acc_mps, 100.0));
  return 20;
}

static uint16_t velned(const struct ubx_epoch *e, uint8_t *p) {
  const struct nmea_solution *f = &e->fix;
  const int v = f->valid;
  u4(p, e->itow_ms);
  i4(p + 4, v ? scaled_i4(f->north_mps, 100.0) : 0);
  i4(p + 8, v ? scaled_i4(f->east_mps, 100.0) : 0);
  i4(p + 12, v ? scaled_i4(-f->up_mps, 100.0) : 0);
  u4(p + 16, v ? scaled_u4(sqrt(f->speed_mps * f->speed_mps + f->up_mps * f->up_mps), 100.0) : 0);
  u4(p + 20, v ? scaled_u4(f->speed_mps, 100.0) : 0);
  i4(p + 24, v ? scaled_i4(f->course_deg, 1e5) : 0);
  u4(p + 28, acc(e, e->s_acc_mps, 100.0));
  /* Heading 1 sigma: a per-axis velocity error s across a ground speed v turns it by s / v rad
   * (s = sAcc / sqrt(3), the per-axis part of the 3D figure); at most 180 degrees. */
  double c = 180.0;
  if (v && f->speed_mps > 0.0) c = fmin(180.0, e->s_acc_mps / sqrt(3.0) / f->speed_mps / DEG);
  u4(p + 32, acc(e, c, 1e5));
  return 36;
}

static uint16_t timegps(const struct ubx_epoch *e, uint8_t *p) {
  const int t = e->fix.time_valid;
  u4(p, e->itow_ms);
  i4(p + 4, 0);
  u2(p + 8, t ? (uint16_t)e->week : 0u);
  u1(p + 10, UBX_LEAP_SECONDS);
  u1(p + 11, t ? TIME_TOW_VALID | TIME_WEEK_VALID | TIME_LEAP_VALID : 0u);
  u4(p + 12, t ? 50u : UNKNOWN_ACCURACY); /* tAcc ns: a PPS-grade 50 ns (NEO-6 datasheet: 30 ns RMS) */
  return 16;
}

static uint16_t timeutc(const struct ubx_epoch *e, uint8_t *p) {
  memset(p, 0, 20);
  const int t = e->fix.time_valid;
  u4(p, e->itow_ms);
  u4(p + 4, t ? 50u : UNKNOWN_ACCURACY);
  i4(p + 8, 0);
  if (t) {
    struct nmea_utc u;
    nmea_utc_from_unix_ms(e->fix.utc_ms, &u);
    u2(p + 12, (unsigned)u.year);
    u1(p + 14, (unsigned)u.month);
    u1(p + 15, (unsigned)u.day);
    u1(p + 16, (unsigned)u.hour);
    u1(p + 17, (unsigned)u.minute);
    u1(p + 18, (unsigned)u.second);
    u1(p + 19, TIME_TOW_VALID | TIME_WEEK_VALID | TIME_LEAP_VALID);
  }
  return 20;
}

static uint16_t svinfo(const struct ubx_epoch *e, uint8_t *p) {
  const struct nmea_solution *f = &e->fix;
  u4(p, e->itow_ms);
  u1(p + 4, (unsigned)f->in_view);
  u1(p + 5, CHIP_GEN_UBLOX6);
  u2(p + 6, 0);
  for (int i = 0; i < f->in_view; ++i) {
    uint8_t *c = p + 8 + 12 * i;
    const struct nmea_satellite *s = &f->sky[i];
    int used = 0;
    for (int k = 0; f->valid && k < f->used_count; ++k) used |= f->used_prn[k] == s->prn;
    const int orbit = s->elevation_deg >= 0;
    u1(c, (unsigned)i);
    u1(c + 1, (unsigned)s->prn);
    u1(c + 2, (used ? SV_USED : 0u) | (orbit ? SV_ORBIT_AVAIL | SV_ORBIT_EPH : 0u));
    u1(c + 3, used ? QUALITY_CARRIER_LOCK : QUALITY_CODE_LOCK);
    u1(c + 4, (unsigned)s->snr_dbhz);
    u1(c + 5, orbit ? (unsigned)s->elevation_deg : 0u);
    u2(c + 6, orbit ? (unsigned)s->azimuth_deg : 0u);
    i4(c + 8, 0); /* prRes: pseudorange residuals are not modelled */
  }
  return (uint16_t)(8 + 12 * f->in_view);
}

static uint16_t sbas(const struct ubx_epoch *e, uint8_t *p) {
  memset(p, 0, 12);
  u4(p, e->itow_ms);
  /* No SBAS satellite in the model's sky: geo 0, system unknown, no services, no entries. */
  u1(p + 5, e->sbas_enabled ? 1u : 0u); /* mode: 1 enabled integrity, 0 disabled */
  p[6] = (uint8_t)(int8_t)SBAS_SYS_UNKNOWN;
  return 12;
}

uint16_t ubx_nav_payload(enum ubx_nav_msg m, const struct ubx_epoch *e, uint8_t *out) {
  switch (m) {
    case UBX_NAV_POSECEF: return posecef(e, out);
    case UBX_NAV_POSLLH: return posllh(e, out);
    case UBX_NAV_STATUS: return status(e, out);
    case UBX_NAV_DOP: return dop(e, out);
    case UBX_NAV_SOL: return sol(e, out);
    case UBX_NAV_VELECEF: return velecef(e, out);
    case UBX_NAV_VELNED: return velned(e, out);
    case UBX_NAV_TIMEGPS: return timegps(e, out);
    case UBX_NAV_TIMEUTC: return timeutc(e, out);
    case UBX_NAV_SVINFO: return svinfo(e, out);
    case UBX_NAV_SBAS: return sbas(e, out);
    case UBX_NAV_MSGS: break;
  }
  return 0;
}
