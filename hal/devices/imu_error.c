/* Inertial sensor errors: constant draws at init, a Wiener-process bias, white noise per sample. */
#include "imu_error.h"

#include <math.h>
#include <string.h>

#include "noise.h"

/* Separate streams of one seed, so a change in how many noise samples were taken never moves the
 * part's turn-on draws or its bias walk (any distinct odd constants do). */
#define STREAM_PART UINT64_C(0x2545F4914F6CDD1D)
#define STREAM_WALK UINT64_C(0x9FB21C651E98DF25)
#define STREAM_NOISE UINT64_C(0xC2B2AE3D27D4EB4F)

void imu_error_init(struct imu_error *e, const struct imu_error_figures *fig, uint64_t seed) {
  memset(e, 0, sizeof *e);
  e->fig = *fig;
  e->seed = seed;
  const uint64_t part = seed ^ STREAM_PART;
  for (int i = 0; i < 3; ++i) {
    e->bias[i] = fig->turn_on_bias[i] * noise_gaussian(part, (uint64_t)i);
    for (int j = 0; j < 3; ++j) {
      const double d = noise_gaussian(part, (uint64_t)(3 + 3 * i + j));
      e->gain[i][j] = (i == j) ? 1.0 + fig->scale_error * d : fig->cross_axis * d;
    }
  }
}

void imu_error_walk(struct imu_error *e, double dt_s) {
  if (e->fig.bias_walk <= 0.0 || dt_s <= 0.0) return;
  const double sd = e->fig.bias_walk * sqrt(dt_s);
  const uint64_t stream = e->seed ^ STREAM_WALK;
  for (int i = 0; i < 3; ++i) e->bias[i] += sd * noise_gaussian(stream, 3u * e->walk_steps + (uint64_t)i);
  ++e->walk_steps;
}

void imu_error_apply(const struct imu_error *e, const double truth[3], double rate_hz, uint64_t index,
                     double out[3]) {
  const double sd = e->fig.noise_density > 0.0 ? e->fig.noise_density * sqrt(0.5 * rate_hz) : 0.0;
  const uint64_t stream = e->seed ^ STREAM_NOISE;
  for (int i = 0; i < 3; ++i) {
    double v = e->bias[i];
    for (int j = 0; j < 3; ++j) v += e->gain[i][j] * truth[j];
    if (sd > 0.0) v += sd * noise_gaussian(stream, 3u * index + (uint64_t)i);
    out[i] = v;
  }
}
