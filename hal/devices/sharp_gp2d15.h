/* Sharp GP2D15 infrared proximity switch (digital, judgement distance 24 cm): a distance
 * comparator with hysteresis behind an open-collector output with an internal 12 kOhm pull-up. */
#ifndef SEAR_DEVICES_SHARP_GP2D15_H
#define SEAR_DEVICES_SHARP_GP2D15_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Electro-optical characteristics table, "distance characteristics of output" Vo (note *2: each
 * unit is adjusted at shipment to switch at 24 cm +- 3 cm on 90 % white paper). */
#define GP2D15_SWITCH_DISTANCE_MIN_M 0.21
#define GP2D15_SWITCH_DISTANCE_TYP_M 0.24
#define GP2D15_SWITCH_DISTANCE_MAX_M 0.27

/* Note *4 says the output switching has a hysteresis width but gives no figure; this default is
 * our choice (see sharp_gp2d15.c). */
#define GP2D15_HYSTERESIS_DEFAULT_M 0.01

/* Pin levels. Note *4: the specified distance is where the output goes from L to H, i.e. H is
 * "object within the judgement distance". */
#define GP2D15_LEVEL_DETECTED 1
#define GP2D15_LEVEL_CLEAR 0

/* Output stage (Fig. 2 block diagram and the table): open collector, 12 kOhm pull-up to Vcc
 * inside the unit; VOH >= Vcc - 0.3 V, VOL <= 0.6 V. */
#define GP2D15_PULLUP_OHM 12000.0
#define GP2D15_VOH_BELOW_VCC_MAX_V 0.3
#define GP2D15_VOL_MAX_V 0.6

/* Timing chart (Fig. 3): the same 38.3 ms +- 9.6 ms measuring cycle as the GP2D12; the judgement
 * appears 7.6 ms +- 1.9 ms after the measurement ends. */
#define GP2D15_PERIOD_NS INT64_C(38300000)
#define GP2D15_PERIOD_TOLERANCE_NS INT64_C(9600000)
#define GP2D15_OUTPUT_DELAY_TYP_NS INT64_C(7600000)
#define GP2D15_OUTPUT_DELAY_TOLERANCE_NS INT64_C(1900000)

struct gp2d15 {
  double switch_distance_m; /* approaching closer than this turns the output H */
  double hysteresis_m;      /* receding past switch_distance_m + this turns it back L */
  int detected;             /* current judgement, 1 or 0 */
};

/* Sets up a unit with the given switching distance (must lie in the datasheet's 21-27 cm spread)
 * and hysteresis (finite, >= 0), output L. Returns 0, or -1 with *sensor untouched if a value is
 * out of range. */
int gp2d15_init(struct gp2d15 *sensor, double switch_distance_m, double hysteresis_m);

/* A typical unit: 24 cm, GP2D15_HYSTERESIS_DEFAULT_M, output L. */
void gp2d15_init_typical(struct gp2d15 *sensor);

/* One measurement (call once per GP2D15_PERIOD_NS) of a target at distance_m; returns the new
 * pin level. A negative, NaN or infinite distance means "nothing hit". */
int gp2d15_update(struct gp2d15 *sensor, double distance_m);

/* The pin level the last measurement left. */
int gp2d15_level(const struct gp2d15 *sensor);

#ifdef __cplusplus
}
#endif
#endif
