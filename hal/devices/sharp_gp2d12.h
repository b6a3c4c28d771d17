/* Sharp GP2D12 infrared ranger (analog, 10-80 cm): the typical distance-to-volts transfer curve
 * and the sample-and-hold timing of its 38.3 ms measuring cycle. Distances in metres, output in
 * volts at Vcc = 5 V, times in integer nanoseconds since the sensor was powered. */
#ifndef SEAR_DEVICES_SHARP_GP2D12_H
#define SEAR_DEVICES_SHARP_GP2D12_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Electro-optical characteristics table (Ta = 25 C, Vcc = 5 V, 90 % white paper). */
#define GP2D12_MIN_RANGE_M 0.10    /* distance measuring range dL, 10 cm ... */
#define GP2D12_MAX_RANGE_M 0.80    /* ... to 80 cm */
#define GP2D12_V80_MIN_V 0.25      /* output voltage Vo at L = 80 cm: min 0.25, */
#define GP2D12_V80_TYP_V 0.40      /* typ 0.4, */
#define GP2D12_V80_MAX_V 0.55      /* max 0.55 V */
#define GP2D12_DELTA_V_MIN_V 1.75  /* output change dVo from L = 80 cm to 10 cm: min 1.75, */
#define GP2D12_DELTA_V_TYP_V 2.0   /* typ 2.0, */
#define GP2D12_DELTA_V_MAX_V 2.25  /* max 2.25 V */
#define GP2D12_VCC_V 5.0           /* the table's (and the curve's) supply */

/* Not from the datasheet (it says nothing past 80 cm): the output with nothing in range, and the
 * distance beyond which the model holds it. See sharp_gp2d12.c for the reasoning. */
#define GP2D12_NO_OBJECT_V 0.25
#define GP2D12_CURVE_END_M 1.50

/* Timing chart (Fig. 3): one distance measurement every 38.3 ms +- 9.6 ms; its result appears on
 * Vo at most 5.0 ms after the measurement ends and is held until the next one. Before the first
 * result the output is unstable. */
#define GP2D12_PERIOD_NS INT64_C(38300000)
#define GP2D12_PERIOD_TOLERANCE_NS INT64_C(9600000)
#define GP2D12_OUTPUT_DELAY_MAX_NS INT64_C(5000000)

/* Typical output (V) for a 90 % white target at distance_m. Covers 0 (contact, 0 V) through the
 * fold-back peak near 8 cm, the 10-80 cm range, and a slow approach to GP2D12_NO_OBJECT_V that
 * is reached at GP2D12_CURVE_END_M. A negative, NaN or infinite distance means "nothing hit" and
 * gives GP2D12_NO_OBJECT_V. */
double gp2d12_output_v(double distance_m);

/* One held output sample: the typical curve plus Gaussian noise of noise_sd_v (V), drawn from
 * noise_gaussian(seed, sample_index) so sample k is the same whatever was sampled before it.
 * Clamped to 0..GP2D12_VCC_V because the output stage cannot leave its rails. noise_sd_v <= 0
 * gives the bare curve. */
double gp2d12_sample_v(double distance_m, uint64_t seed, uint64_t sample_index, double noise_sd_v);

/* Index of the measurement whose result Vo shows at t_ns after power-on, taking the typical
 * period and the worst-case output delay: measurement k runs over [k, k+1) periods and is shown
 * from (k+1) periods + 5 ms on. Returns -1 while the output is still unstable. */
int64_t gp2d12_output_index(int64_t t_ns);

#ifdef __cplusplus
}
#endif
#endif
