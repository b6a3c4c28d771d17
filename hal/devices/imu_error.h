/* The error model of one 3-axis MEMS inertial sensor (a gyro or an accelerometer): turn-on bias,
 * bias random walk, scale factor, axis misalignment and white noise, all drawn from noise.h so
 * draw k is a pure function of (seed, k). SI units in and out (rad/s or m/s^2). */
#ifndef SEAR_DEVICES_IMU_ERROR_H
#define SEAR_DEVICES_IMU_ERROR_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Every figure is one standard deviation; 0 switches that error off. */
struct imu_error_figures {
  /* One-sided white-noise density (unit/sqrt(Hz)), the datasheet's "noise spectral density": a
   * sample taken at rate fs carries sd = density * sqrt(fs / 2), so the RMS in a bandwidth B is
   * density * sqrt(B) (the datasheet's own "total RMS noise") and the Allan deviation of the
   * stationary output is density / sqrt(2 tau). */
  double noise_density;
  double turn_on_bias[3];  /* unit, per axis; drawn once at init */
  /* Bias random walk (unit/sqrt(s)): the bias after t seconds has wandered by sd walk * sqrt(t),
   * so its Allan deviation is walk * sqrt(tau / 3). */
  double bias_walk;
  double scale_error;     /* relative, per axis */
  double cross_axis;      /* relative coupling of each axis into each other one */
};

struct imu_error {
  struct imu_error_figures fig;
  uint64_t seed;
  double bias[3];       /* current bias, turn-on plus walk */
  double gain[3][3];    /* I + scale errors (diagonal) + cross-axis coupling (off diagonal) */
  uint64_t walk_steps;  /* bias-walk draws taken so far */
};

/* Draws the turn-on bias, scale and misalignment of this part from `seed`. */
void imu_error_init(struct imu_error *e, const struct imu_error_figures *fig, uint64_t seed);
/* Walks the bias over dt_s: one Gaussian step of sd bias_walk * sqrt(dt_s) per axis. */
void imu_error_walk(struct imu_error *e, double dt_s);
/* What the sensing element outputs for `truth` when sampled at rate_hz, sample number `index`
 * (the index picks the noise draw, so the same index always gets the same noise). */
void imu_error_apply(const struct imu_error *e, const double truth[3], double rate_hz, uint64_t index,
                     double out[3]);

#ifdef __cplusplus
}
#endif
#endif
