/* Gauss-Markov position error on a 100 ms grid, velocity noise, TTFF and a fixed sky with its
 * dilution of precision. */
#include "gnss_error.h"

#include <math.h>
#include <stddef.h>

#include "noise.h"

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)
#define MAX_CORRELATION_S 3600.0 /* keeps the moving sum's window (8 tau) at 288000 ticks */
#define MIN_CORRELATION_S 0.1
/* The moving sum is cut after this many time constants: the dropped tail holds exp(-16) of the
 * variance and is renormalised away (weight below). */
#define WINDOW_TAUS 8.0

/* WGS-84: NIMA TR8350.2 table 3.1. */
#define WGS84_A 6378137.0
#define WGS84_F (1.0 / 298.257223563)

/* A fixed, plausible mid-latitude GPS sky: PRNs and positions are made up, spread in azimuth
 * so that each added satellite improves the geometry; C/N0 rises with elevation as the antenna
 * gain and the path through the atmosphere make it on a patch antenna (about 30 dBHz near the
 * horizon to 48 dBHz at the zenith). Highest first: a receiver fills its solution with the best
 * satellites. */
static const struct gnss_sky_satellite sky[GNSS_SKY_SATELLITES] = {
    {5, 72, 40, 47},   {12, 55, 290, 45},  {15, 48, 130, 44}, {18, 38, 210, 42},
    {21, 30, 330, 40}, {24, 25, 70, 38},   {26, 20, 170, 37}, {29, 15, 250, 35},
    {2, 12, 10, 33},   {10, 10, 100, 32},  {13, 8, 300, 30},  {17, 6, 200, 28},
};

const struct gnss_sky_satellite *gnss_error_sky(void) { return sky; }

/* Inverts the 4x4 normal matrix in place by Gauss-Jordan with partial pivoting. */
static int invert4(double a[4][4]) {
  double inv[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  for (int c = 0; c < 4; ++c) {
    int p = c;
    for (int r = c + 1; r < 4; ++r)
      if (fabs(a[r][c]) > fabs(a[p][c])) p = r;
    if (fabs(a[p][c]) < 1e-12) return 0;
    for (int k = 0; k < 4; ++k) {
      double t = a[c][k]; a[c][k] = a[p][k]; a[p][k] = t;
      t = inv[c][k]; inv[c][k] = inv[p][k]; inv[p][k] = t;
    }
    const double d = a[c][c];
    for (int k = 0; k < 4; ++k) {
      a[c][k] /= d;
      inv[c][k] /= d;
    }
    for (int r = 0; r < 4; ++r) {
      if (r == c) continue;
      const double f = a[r][c];
      for (int k = 0; k < 4; ++k) {
        a[r][k] -= f * a[c][k];
        inv[r][k] -= f * inv[c][k];
      }
    }
  }
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k) a[r][k] = inv[r][k];
  return 1;
}

int gnss_dop(const struct gnss_sky_satellite *sats, int count, double *pdop, double *hdop, double *vdop) {
  double n[4][4] = {{0}};
  for (int i = 0; i < count; ++i) {
    const double el = sats[i].elevation_deg * DEG, az = sats[i].azimuth_deg * DEG;
    /* Line of sight to the satellite in east, north, up, and the receiver clock column. */
    const double g[4] = {-cos(el) * sin(az), -cos(el) * cos(az), -sin(el), 1.0};
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) n[r][c] += g[r] * g[c];
  }
  if (count < 4 || !invert4(n)) return 0;
  *hdop = sqrt(n[0][0] + n[1][1]);
  *vdop = sqrt(n[2][2]);
  *pdop = sqrt(n[0][0] + n[1][1] + n[2][2]);
  return 1;
}

void gnss_error_defaults(struct gnss_error_config *c) {
  c->cep_m = GNSS_DEFAULT_CEP_M;
  c->vertical_sd_m = 0.0; /* from the geometry */
  c->velocity_sd_mps = GNSS_DEFAULT_VELOCITY_SD_MPS;
  c->correlation_s = GNSS_DEFAULT_CORRELATION_S;
  c->ttff_s = GNSS_DEFAULT_TTFF_S;
  c->seed = 0;
}

void gnss_error_init(struct gnss_error *m, const struct gnss_error_config *c) {
  struct gnss_error_config k = *c;
  if (!(k.cep_m > 0.0)) k.cep_m = GNSS_DEFAULT_CEP_M;
  if (!(k.velocity_sd_mps >= 0.0)) k.velocity_sd_mps = GNSS_DEFAULT_VELOCITY_SD_MPS;
  if (!(k.correlation_s > 0.0)) k.correlation_s = GNSS_DEFAULT_CORRELATION_S;
  if (k.correlation_s < MIN_CORRELATION_S) k.correlation_s = MIN_CORRELATION_S;
  if (k.correlation_s > MAX_CORRELATION_S) k.correlation_s = MAX_CORRELATION_S;
  if (!(k.ttff_s >= 0.0)) k.ttff_s = GNSS_DEFAULT_TTFF_S;
  m->config = k;
  m->sigma_horizontal_m = k.cep_m / GNSS_CEP_PER_SIGMA;

  /* The horizontal RMS error (DRMS, sqrt(2) sigma per axis) is HDOP * UERE. A receiver that
   * shows a poor CEP sees few satellites or a poor geometry, not a worse signal: pick the
   * number of satellites whose HDOP makes the implied UERE nearest GNSS_NOMINAL_UERE_M. */
  const double drms = sqrt(2.0) * m->sigma_horizontal_m;
  double best = INFINITY;
  for (int n = GNSS_MIN_USED; n <= GNSS_SKY_SATELLITES; ++n) {
    double p, h, v;
    if (!gnss_dop(sky, n, &p, &h, &v)) continue;
    const double miss = fabs(log(drms / h / GNSS_NOMINAL_UERE_M));
    if (miss < best) {
      best = miss;
      m->used_count = n;
      m->pdop = p;
      m->hdop = h;
      m->vdop = v;
    }
  }
  m->uere_m = drms / m->hdop;
  m->sigma_vertical_m = k.vertical_sd_m > 0.0 ? k.vertical_sd_m : m->uere_m * m->vdop;

  const double ticks_per_tau = k.correlation_s / ((double)GNSS_ERROR_TICK_NS * 1e-9);
  m->phi = exp(-1.0 / ticks_per_tau);
  m->window = (int64_t)ceil(WINDOW_TAUS * ticks_per_tau);
  m->phi_window = pow(m->phi, (double)m->window);
  /* Scales the truncated sum to unit variance: sum phi^2j over the window is
   * (1 - phi^2J) / (1 - phi^2). */
  m->weight = sqrt((1.0 - m->phi * m->phi) / (1.0 - m->phi_window * m->phi_window));
  m->cached_tick = -1;
}

/* Separate streams per axis so east, north and up are independent. */
static uint64_t axis_seed(const struct gnss_error *m, unsigned stream) { return noise_hash64(m->config.seed, stream); }

static double white(const struct gnss_error *m, unsigned axis, int64_t tick) {
  return noise_gaussian(axis_seed(m, axis), (uint64_t)tick); /* negative ticks wrap to their own draws */
}

/* S_k = sum_{j<J} phi^j w_{k-j}: a first-order Gauss-Markov (AR(1)) process whose memory is cut
 * after J ticks. Computed directly at anchors k = nJ and stepped by
 * S_k = phi S_{k-1} + w_k - phi^J w_{k-J} between them, so the value at a tick depends on that
 * tick alone (the same anchor, the same steps), never on which ticks were asked before. */
static void moving_sum(struct gnss_error *m, int64_t tick) {
  const int64_t anchor = tick / m->window * m->window;
  if (m->cached_tick < anchor || m->cached_tick > tick) {
    for (unsigned a = 0; a < 3; ++a) {
      double s = 0.0;
      for (int64_t i = anchor - m->window + 1; i <= anchor; ++i) s = m->phi * s + white(m, a, i);
      m->cached_sum[a] = s;
    }
    m->cached_tick = anchor;
  }
  while (m->cached_tick < tick) {
    const int64_t k = ++m->cached_tick;
    for (unsigned a = 0; a < 3; ++a)
      m->cached_sum[a] = m->phi * m->cached_sum[a] + white(m, a, k) - m->phi_window * white(m, a, k - m->window);
  }
}

void gnss_error_at(struct gnss_error *m, int64_t since_power_on_ns, struct gnss_error_sample *out) {
  const int64_t tick = since_power_on_ns > 0 ? since_power_on_ns / GNSS_ERROR_TICK_NS : 0;
  moving_sum(m, tick);
  out->east_m = m->sigma_horizontal_m * m->weight * m->cached_sum[0];
  out->north_m = m->sigma_horizontal_m * m->weight * m->cached_sum[1];
  out->up_m = m->sigma_vertical_m * m->weight * m->cached_sum[2];
  const double v = m->config.velocity_sd_mps;
  out->east_mps = v * white(m, 3, tick);
  out->north_mps = v * white(m, 4, tick);
  out->up_mps = v * white(m, 5, tick);
}

int gnss_error_has_fix(const struct gnss_error *m, int64_t since_start_ns) {
  return (double)since_start_ns >= m->config.ttff_s * 1e9;
}

int gnss_error_tracked(const struct gnss_error *m, int64_t since_start_ns) {
  if (gnss_error_has_fix(m, since_start_ns)) return GNSS_SKY_SATELLITES;
  const double t = (double)since_start_ns * 1e-9 - GNSS_FIRST_ACQUISITION_S;
  if (t < 0.0) return 0;
  const double n = 1.0 + floor(t / GNSS_ACQUISITION_STEP_S);
  return n > GNSS_SKY_SATELLITES ? GNSS_SKY_SATELLITES : (int)n;
}

void gnss_offset_position(double *latitude_deg, double *longitude_deg, double *height_m, double east_m,
                          double north_m, double up_m) {
  const double e2 = WGS84_F * (2.0 - WGS84_F);
  const double s = sin(*latitude_deg * DEG);
  const double w = sqrt(1.0 - e2 * s * s);
  const double prime_vertical = WGS84_A / w;            /* N: east-west radius of curvature */
  const double meridian = WGS84_A * (1.0 - e2) / (w * w * w); /* M: north-south radius */
  const double cos_lat = cos(*latitude_deg * DEG);
  *latitude_deg += north_m / (meridian + *height_m) / DEG;
  *longitude_deg += east_m / ((prime_vertical + *height_m) * cos_lat) / DEG;
  if (*longitude_deg > 180.0) *longitude_deg -= 360.0;
  if (*longitude_deg <= -180.0) *longitude_deg += 360.0;
  *height_m += up_m;
}
