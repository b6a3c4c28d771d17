/* Quadrature encoder: edges are the crossing times of quarter-cycle boundaries by a shaft moving
 * linearly between motion updates. */
#include "quadrature_encoder.h"

#include <math.h>

#define TWO_PI 6.283185307179586476925286766559
#define NONE INT64_MAX

static int64_t quarter_of(const struct quadrature_encoder *s, double angle_rad) {
  return (int64_t)floor(angle_rad / s->quarter_rad);
}

/* Gray sequence over quarters: A = 1 in quarters 1 and 2, B = 1 in quarters 2 and 3 (mod 4). */
static int levels_of(int64_t quarter) {
  const int64_t q = ((quarter % 4) + 4) % 4;
  const int a = q == 1 || q == 2;
  const int b = q == 2 || q == 3;
  return a | (b << 1);
}

void encoder_init(struct quadrature_encoder *s, uint32_t counts_per_rev, double angle_rad) {
  s->counts_per_rev = counts_per_rev ? counts_per_rev : 1u;
  s->quarter_rad = TWO_PI / (4.0 * (double)s->counts_per_rev);
  s->motion_t_ns = 0;
  s->motion_angle_rad = angle_rad;
  s->motion_rate_radps = 0.0;
  s->motion_quarter = quarter_of(s, angle_rad);
  s->shown_quarter = s->motion_quarter;
  s->catching_up = 0;
}

void encoder_set_motion(struct quadrature_encoder *s, double angle_rad, double rate_radps, int64_t t_ns) {
  s->motion_t_ns = t_ns;
  s->motion_angle_rad = angle_rad;
  s->motion_rate_radps = rate_radps;
  s->motion_quarter = quarter_of(s, angle_rad);
  s->catching_up = s->shown_quarter != s->motion_quarter;
}

/* The boundary between quarters m - 1 and m is at angle m * quarter_rad. */
static int64_t crossing_ns(const struct quadrature_encoder *s, int64_t boundary) {
  const double distance = (double)boundary * s->quarter_rad - s->motion_angle_rad;
  double dt = distance / s->motion_rate_radps;
  if (dt < 0.0) dt = 0.0; /* floor() and the product may disagree by an ulp at a boundary */
  const double ns = dt * 1e9;
  if (ns >= 9.0e18) return NONE;
  return s->motion_t_ns + (int64_t)llround(ns);
}

int64_t encoder_next_edge_ns(const struct quadrature_encoder *s) {
  if (s->catching_up) return s->motion_t_ns;
  if (s->motion_rate_radps > 0.0) return crossing_ns(s, s->shown_quarter + 1);
  if (s->motion_rate_radps < 0.0) return crossing_ns(s, s->shown_quarter);
  return NONE;
}

void encoder_take_edge(struct quadrature_encoder *s, int *channel, int *level) {
  int step;
  if (s->catching_up)
    step = s->motion_quarter > s->shown_quarter ? 1 : -1;
  else
    step = s->motion_rate_radps > 0.0 ? 1 : (s->motion_rate_radps < 0.0 ? -1 : 0);
  const int before = levels_of(s->shown_quarter);
  s->shown_quarter += step;
  /* Caught up: from here on the motion's own crossings count from the shown quarter. */
  if (s->shown_quarter == s->motion_quarter) s->catching_up = 0;
  const int after = levels_of(s->shown_quarter);
  const int changed = before ^ after;
  const int ch = changed & 2 ? 1 : 0;
  if (channel) *channel = ch;
  if (level) *level = (after >> ch) & 1;
}

int encoder_levels(const struct quadrature_encoder *s) { return levels_of(s->shown_quarter); }

int64_t encoder_count(const struct quadrature_encoder *s) { return s->shown_quarter; }

double encoder_count_angle_rad(const struct quadrature_encoder *s) { return (double)s->shown_quarter * s->quarter_rad; }
