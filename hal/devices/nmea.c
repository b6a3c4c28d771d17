/* NMEA 0183 sentence layouts and checksums, civil time, and a UART transmit queue that stamps
 * every byte with the end of its stop bit. */
#include "nmea.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#define KNOTS_PER_MPS (3600.0 / 1852.0) /* the international nautical mile is 1852 m exactly */
#define KMH_PER_MPS 3.6

uint8_t nmea_checksum(const char *s, size_t n) {
  uint8_t x = 0;
  for (size_t i = 0; i < n; ++i) x = (uint8_t)(x ^ (uint8_t)s[i]);
  return x;
}

size_t nmea_finish(char *out, size_t cap, const char *body) {
  const size_t n = strlen(body);
  const size_t total = n + 6; /* '$', body, '*', two hex digits, CR, LF */
  if (total > NMEA_MAX_SENTENCE || total + 1 > cap) return 0;
  static const char hex[] = "0123456789ABCDEF";
  const uint8_t c = nmea_checksum(body, n);
  out[0] = '$';
  memcpy(out + 1, body, n);
  out[n + 1] = '*';
  out[n + 2] = hex[c >> 4];
  out[n + 3] = hex[c & 15];
  out[n + 4] = '\r';
  out[n + 5] = '\n';
  out[n + 6] = '\0';
  return total;
}

static int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

int nmea_parse_frame(const char *s, size_t n, const char **body, size_t *body_len) {
  while (n > 0 && (s[n - 1] == '\r' || s[n - 1] == '\n')) --n;
  if (n < 4 || s[0] != '$' || s[n - 3] != '*') return 0;
  const int hi = hex_value(s[n - 2]), lo = hex_value(s[n - 1]);
  if (hi < 0 || lo < 0) return 0;
  if (nmea_checksum(s + 1, n - 4) != (uint8_t)(hi * 16 + lo)) return 0;
  *body = s + 1;
  *body_len = n - 4;
  return 1;
}

/* Days from civil and back: H. Hinnant's algorithms ("chrono-Compatible Low-Level Date
 * Algorithms"), exact over the proleptic Gregorian calendar. */
static int64_t days_from_civil(int64_t y, int64_t m, int64_t d) {
  y -= m <= 2;
  const int64_t era = (y >= 0 ? y : y - 399) / 400;
  const int64_t yoe = y - era * 400;
  const int64_t doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + doe - 719468;
}

int64_t nmea_unix_s(int year, int month, int day, int hour, int minute, int second) {
  return days_from_civil(year, month, day) * 86400 + hour * 3600 + minute * 60 + second;
}

void nmea_utc_from_unix_ms(int64_t unix_ms, struct nmea_utc *out) {
  int64_t days = unix_ms / 86400000;
  int64_t ms = unix_ms % 86400000;
  if (ms < 0) {
    ms += 86400000;
    --days;
  }
  const int64_t z = days + 719468;
  const int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const int64_t doe = z - era * 146097;
  const int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const int64_t mp = (5 * doy + 2) / 153;
  const int64_t d = doy - (153 * mp + 2) / 5 + 1;
  const int64_t m = mp < 10 ? mp + 3 : mp - 9;
  out->year = (int)(yoe + era * 400 + (m <= 2));
  out->month = (int)m;
  out->day = (int)d;
  out->hour = (int)(ms / 3600000);
  out->minute = (int)(ms / 60000 % 60);
  out->second = (int)(ms / 1000 % 60);
  out->millisecond = (int)(ms % 1000);
}

/* ---- sentence text ---- */

struct text {
  char s[160]; /* longer than any sentence, so an over-long one is caught by nmea_finish */
  size_t n;
};

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static void put(struct text *t, const char *fmt, ...) {
  if (t->n >= sizeof t->s) return;
  va_list ap;
  va_start(ap, fmt);
  const int k = vsnprintf(t->s + t->n, sizeof t->s - t->n, fmt, ap);
  va_end(ap);
  if (k > 0) t->n += (size_t)k;
  if (t->n >= sizeof t->s) t->n = sizeof t->s - 1;
}

static long long pow10i(int k) {
  long long p = 1;
  while (k-- > 0) p *= 10;
  return p;
}

/* ddmm.mmmm,N: rounded once, in whole units of the last decimal of a minute, so 59.999995'
 * carries into the degrees instead of printing as 60.00000. */
static void put_angle(struct text *t, double deg, int degree_digits, int decimals, char pos, char neg) {
  const long long scale = pow10i(decimals);
  const long long units = llround(fabs(deg) * 60.0 * (double)scale);
  const long long whole = units / (60 * scale), rest = units % (60 * scale);
  put(t, "%0*lld%02lld.%0*lld,%c", degree_digits, whole, rest / scale, decimals, rest % scale, deg < 0 ? neg : pos);
}

static void put_time(struct text *t, const struct nmea_style *st, const struct nmea_solution *f) {
  if (!f->time_valid) return;
  struct nmea_utc u;
  nmea_utc_from_unix_ms(f->utc_ms, &u);
  const int frac = st->time_decimals >= 3 ? u.millisecond : u.millisecond / 10;
  put(t, "%02d%02d%02d.%0*d", u.hour, u.minute, u.second, st->time_decimals >= 3 ? 3 : 2, frac);
}

static void put_date(struct text *t, const struct nmea_solution *f) {
  if (!f->time_valid) return;
  struct nmea_utc u;
  nmea_utc_from_unix_ms(f->utc_ms, &u);
  put(t, "%02d%02d%02d", u.day, u.month, u.year % 100);
}

static void put_position(struct text *t, const struct nmea_style *st, const struct nmea_solution *f) {
  if (!f->valid) {
    put(t, ",,,");
    return;
  }
  put_angle(t, f->latitude_deg, 2, st->minute_decimals, 'N', 'S');
  put(t, ",");
  put_angle(t, f->longitude_deg, 3, st->minute_decimals, 'E', 'W');
}

static size_t finish(char *out, size_t cap, struct text *t) { return nmea_finish(out, cap, t->s); }

size_t nmea_rmc(char *out, size_t cap, const struct nmea_style *st, const struct nmea_solution *f) {
  struct text t = {{0}, 0};
  put(&t, "GPRMC,");
  put_time(&t, st, f);
  put(&t, ",%c,", f->valid ? 'A' : 'V');
  put_position(&t, st, f);
  if (f->valid)
    put(&t, ",%.*f,%.2f,", st->speed_decimals, f->speed_mps * KNOTS_PER_MPS, f->course_deg);
  else
    put(&t, st->time_before_fix ? ",0.00,0.00," : ",,,");
  put_date(&t, f);
  /* Magnetic variation is left empty, as both modules leave it; mode A autonomous / N no fix. */
  put(&t, ",,,%c", f->valid ? 'A' : 'N');
  return finish(out, cap, &t);
}

size_t nmea_vtg(char *out, size_t cap, const struct nmea_style *st, const struct nmea_solution *f) {
  struct text t = {{0}, 0};
  if (f->valid)
    put(&t, "GPVTG,%.2f,T,,M,%.*f,N,%.*f,K,A", f->course_deg, st->speed_decimals, f->speed_mps * KNOTS_PER_MPS,
        st->speed_decimals, f->speed_mps * KMH_PER_MPS);
  else
    put(&t, st->time_before_fix ? "GPVTG,0.00,T,,M,0.00,N,0.00,K,N" : "GPVTG,,,,,,,,,N");
  return finish(out, cap, &t);
}

size_t nmea_gga(char *out, size_t cap, const struct nmea_style *st, const struct nmea_solution *f) {
  struct text t = {{0}, 0};
  put(&t, "GPGGA,");
  put_time(&t, st, f);
  put(&t, ",");
  put_position(&t, st, f);
  const int used = f->valid ? f->used_count : 0;
  put(&t, st->pad_used_count ? ",%d,%02d," : ",%d,%d,", f->valid ? 1 : 0, used);
  if (f->valid)
    put(&t, "%.2f,%.1f,M,%.1f,M,,", f->hdop, f->altitude_msl_m, f->geoid_separation_m);
  else
    put(&t, st->time_before_fix ? ",,M,,M,," : "99.99,,,,,,");
  return finish(out, cap, &t);
}

size_t nmea_gsa(char *out, size_t cap, const struct nmea_style *st, const struct nmea_solution *f) {
  struct text t = {{0}, 0};
  put(&t, "GPGSA,A,%d", f->valid ? 3 : 1);
  for (int i = 0; i < NMEA_MAX_SATELLITES; ++i) {
    if (f->valid && i < f->used_count)
      put(&t, ",%02d", f->used_prn[i]);
    else
      put(&t, ",");
  }
  if (f->valid)
    put(&t, ",%.2f,%.2f,%.2f", f->pdop, f->hdop, f->vdop);
  else
    put(&t, st->time_before_fix ? ",,," : ",99.99,99.99,99.99");
  return finish(out, cap, &t);
}

size_t nmea_gll(char *out, size_t cap, const struct nmea_style *st, const struct nmea_solution *f) {
  struct text t = {{0}, 0};
  put(&t, "GPGLL,");
  put_position(&t, st, f);
  put(&t, ",");
  put_time(&t, st, f);
  put(&t, ",%c,%c", f->valid ? 'A' : 'V', f->valid ? 'A' : 'N');
  return finish(out, cap, &t);
}

size_t nmea_zda(char *out, size_t cap, const struct nmea_style *st, const struct nmea_solution *f) {
  struct text t = {{0}, 0};
  put(&t, "GPZDA,");
  put_time(&t, st, f);
  if (f->time_valid) {
    struct nmea_utc u;
    nmea_utc_from_unix_ms(f->utc_ms, &u);
    put(&t, ",%02d,%02d,%04d,00,00", u.day, u.month, u.year);
  } else {
    put(&t, ",,,,00,00");
  }
  return finish(out, cap, &t);
}

int nmea_gsv_count(const struct nmea_solution *f) { return f->in_view <= 4 ? 1 : (f->in_view + 3) / 4; }

size_t nmea_gsv(char *out, size_t cap, const struct nmea_solution *f, int index) {
  struct text t = {{0}, 0};
  put(&t, "GPGSV,%d,%d,%02d", nmea_gsv_count(f), index + 1, f->in_view);
  for (int i = 4 * index; i < f->in_view && i < 4 * index + 4; ++i) {
    const struct nmea_satellite *s = &f->sky[i];
    put(&t, ",%02d,", s->prn);
    if (s->elevation_deg >= 0) put(&t, "%02d,%03d,", s->elevation_deg, s->azimuth_deg);
    else put(&t, ",,");
    if (s->snr_dbhz > 0) put(&t, "%02d", s->snr_dbhz);
  }
  return finish(out, cap, &t);
}

void nmea_solve(struct nmea_solution *f, struct gnss_error *e, struct gnss_truth_source src, int64_t epoch_ns,
                int64_t power_on_ns, int64_t start_ns, int64_t utc_ms, int time_known) {
  memset(f, 0, sizeof *f);
  const int64_t since_start = epoch_ns - start_ns;
  f->valid = gnss_error_has_fix(e, since_start);
  f->time_valid = f->valid || time_known;
  f->utc_ms = utc_ms;
  const struct gnss_sky_satellite *sky = gnss_error_sky();
  f->in_view = gnss_error_tracked(e, since_start);
  for (int i = 0; i < f->in_view; ++i) {
    f->sky[i].prn = sky[i].prn;
    /* Positions come from the almanac and ephemeris, decoded by the time of the fix. */
    f->sky[i].elevation_deg = f->valid ? sky[i].elevation_deg : -1;
    f->sky[i].azimuth_deg = sky[i].azimuth_deg;
    f->sky[i].snr_dbhz = sky[i].snr_dbhz;
  }
  if (!f->valid) return;
  struct gnss_fix_truth truth;
  memset(&truth, 0, sizeof truth);
  src.fix_at(src.context, epoch_ns, &truth);
  struct gnss_error_sample err;
  gnss_error_at(e, epoch_ns - power_on_ns, &err);
  double lat = truth.latitude_deg, lon = truth.longitude_deg;
  double height = truth.altitude_msl_m + truth.geoid_separation_m; /* ellipsoidal */
  gnss_offset_position(&lat, &lon, &height, err.east_m, err.north_m, err.up_m);
  f->latitude_deg = lat;
  f->longitude_deg = lon;
  f->altitude_msl_m = height - truth.geoid_separation_m;
  f->geoid_separation_m = truth.geoid_separation_m;
  const double ve = truth.east_mps + err.east_mps, vn = truth.north_mps + err.north_mps;
  f->east_mps = ve;
  f->north_mps = vn;
  f->up_mps = truth.up_mps + err.up_mps;
  f->speed_mps = hypot(ve, vn);
  double course = atan2(ve, vn) * (180.0 / 3.14159265358979323846);
  if (course < 0.0) course += 360.0;
  if (course >= 359.995) course = 0.0; /* would print as 360.00 */
  f->course_deg = course;
  f->used_count = e->used_count;
  for (int i = 0; i < e->used_count; ++i) f->used_prn[i] = sky[i].prn;
  f->pdop = e->pdop;
  f->hdop = e->hdop;
  f->vdop = e->vdop;
}

/* ---- transmit queue ---- */

void nmea_tx_init(struct nmea_tx *q, uint32_t baud, size_t buffer_bytes) {
  memset(q, 0, sizeof *q);
  q->line_free_ns = INT64_MIN;
  q->until_ns = INT64_MIN;
  q->gap_from_ns = q->gap_to_ns = INT64_MIN;
  q->baud = baud;
  q->buffer_bytes = buffer_bytes;
}

static const struct nmea_tx_byte *at(const struct nmea_tx *q, uint32_t i) {
  return &q->ring[(q->head + i) & (NMEA_TX_RING - 1)];
}

static int64_t start_of(const struct nmea_tx_byte *b) { return b->end_ns - serial_frame_ns(b->baud); }

size_t nmea_tx_waiting(const struct nmea_tx *q, int64_t t_ns) {
  size_t n = 0;
  for (uint32_t i = q->count; i > 0 && start_of(at(q, i - 1)) >= t_ns; --i) ++n;
  return n;
}

int nmea_tx_queue(struct nmea_tx *q, int64_t ready_ns, const void *bytes, size_t n, int force) {
  /* Whole messages only: a message that does not fit is dropped, never cut. Answers to commands
   * are only limited by what the caller has not yet taken. */
  if ((!force && nmea_tx_waiting(q, ready_ns) + n > q->buffer_bytes) || q->count + n > NMEA_TX_RING) {
    q->dropped_bytes += n;
    return 0;
  }
  const uint8_t *p = (const uint8_t *)bytes;
  const int64_t frame = serial_frame_ns(q->baud);
  int64_t start = q->line_free_ns > ready_ns ? q->line_free_ns : ready_ns;
  for (size_t i = 0; i < n; ++i) {
    struct nmea_tx_byte *b = &q->ring[(q->head + q->count) & (NMEA_TX_RING - 1)];
    b->end_ns = start + frame;
    b->baud = q->baud;
    b->value = p[i];
    ++q->count;
    start = b->end_ns;
  }
  q->line_free_ns = start;
  return 1;
}

void nmea_tx_window(struct nmea_tx *q, int64_t now_ns, int64_t until_ns) {
  if (now_ns > q->until_ns) {
    q->gap_from_ns = q->until_ns;
    q->gap_to_ns = now_ns;
  } else {
    q->gap_from_ns = q->gap_to_ns = INT64_MIN;
  }
  if (until_ns > q->until_ns) q->until_ns = until_ns;
}

size_t nmea_tx_take(struct nmea_tx *q, struct serial_byte *out, size_t cap) {
  size_t n = 0;
  while (q->count > 0) {
    const struct nmea_tx_byte *b = at(q, 0);
    const int lost = b->end_ns >= q->gap_from_ns && start_of(b) < q->gap_to_ns;
    if (!lost) {
      if (b->end_ns >= q->until_ns || n == cap) break;
      out[n].end_ns = b->end_ns;
      out[n].baud = b->baud;
      out[n].value = b->value;
      memset(out[n].reserved, 0, sizeof out[n].reserved);
      ++n;
    }
    q->head = (q->head + 1) & (NMEA_TX_RING - 1);
    --q->count;
  }
  return n;
}
