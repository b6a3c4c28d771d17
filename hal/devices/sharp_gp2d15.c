/* GP2D15 judgement: a comparator on the measured distance with hysteresis. */
#include "sharp_gp2d15.h"

#include <math.h>

/* Why 1 cm of hysteresis when the datasheet gives none: it only has to be wider than the
 * measurement's own jitter at 24 cm so the output does not chatter with a target sitting on the
 * threshold, and narrow enough to vanish inside the +-3 cm switching spread the datasheet does
 * specify. The analog sibling's slope at 24 cm is 40-50 mV/cm, so a few tens of mV of
 * measurement noise is a few mm of distance; 1 cm covers that with margin. */

int gp2d15_init(struct gp2d15 *sensor, double switch_distance_m, double hysteresis_m) {
  /* Written so that NaN fails every test. */
  if (!(switch_distance_m >= GP2D15_SWITCH_DISTANCE_MIN_M && switch_distance_m <= GP2D15_SWITCH_DISTANCE_MAX_M))
    return -1;
  if (!(hysteresis_m >= 0.0 && isfinite(hysteresis_m))) return -1;
  sensor->switch_distance_m = switch_distance_m;
  sensor->hysteresis_m = hysteresis_m;
  /* The timing chart shows the output unstable until the first judgement; starting L is the
   * "nothing seen yet" a firmware would assume. */
  sensor->detected = 0;
  return 0;
}

void gp2d15_init_typical(struct gp2d15 *sensor) {
  (void)gp2d15_init(sensor, GP2D15_SWITCH_DISTANCE_TYP_M, GP2D15_HYSTERESIS_DEFAULT_M);
}

int gp2d15_update(struct gp2d15 *sensor, double distance_m) {
  const int hit = isfinite(distance_m) && distance_m >= 0.0;
  if (!hit) {
    sensor->detected = 0;
  } else if (!sensor->detected) {
    /* Note *4: the 24 cm figure is the L -> H point, i.e. the threshold when approaching. */
    if (distance_m < sensor->switch_distance_m) sensor->detected = 1;
  } else if (distance_m > sensor->switch_distance_m + sensor->hysteresis_m) {
    sensor->detected = 0;
  }
  return gp2d15_level(sensor);
}

int gp2d15_level(const struct gp2d15 *sensor) {
  return sensor->detected ? GP2D15_LEVEL_DETECTED : GP2D15_LEVEL_CLEAR;
}
