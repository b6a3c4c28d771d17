/* HC-SR04: a small state machine on TRIG, scheduling the two ECHO edges of each measurement. */
#include "hcsr04.h"

#include <math.h>

#include "noise.h"

#define NONE INT64_MAX

void hcsr04_init(struct hcsr04 *s, uint64_t seed) {
  s->seed = seed;
  s->measurements = 0;
  s->distance_m[0] = s->distance_m[1] = INFINITY;
  s->distance_t_ns[0] = s->distance_t_ns[1] = INT64_MIN;
  s->trig_level = 0;
  s->trig_rise_ns = INT64_MIN;
  s->last_start_ns = INT64_MIN;
  s->echo_level = 0;
  s->echo_rise_ns = NONE;
  s->echo_fall_ns = NONE;
  s->burst_ns = INT64_MIN;
  s->burst_measurement = 0;
  s->shown_rise_ns = INT64_MIN;
  s->last_width_ns = -1;
}

void hcsr04_set_distance(struct hcsr04 *s, double distance_m, int64_t t_ns) {
  s->distance_m[0] = s->distance_m[1];
  s->distance_t_ns[0] = s->distance_t_ns[1];
  s->distance_m[1] = distance_m;
  s->distance_t_ns[1] = t_ns;
  /* A truth sample for the instant of a burst still to leave, arriving after the trigger: the
   * simulator samples on its own grid, the firmware triggers whenever it likes. */
  if (s->echo_rise_ns != NONE && t_ns <= s->burst_ns)
    s->echo_fall_ns = s->echo_rise_ns + hcsr04_echo_width_ns(distance_m, s->seed, s->burst_measurement);
}

int64_t hcsr04_echo_width_ns(double distance_m, uint64_t seed, uint64_t measurement) {
  /* Written so NaN fails the range test too. */
  if (!(distance_m >= HCSR04_MIN_RANGE_M && distance_m <= HCSR04_MAX_RANGE_M)) return HCSR04_NO_ECHO_NS;
  double noise = noise_gaussian(seed, measurement);
  if (noise > HCSR04_NOISE_CLIP_SD) noise = HCSR04_NOISE_CLIP_SD;
  if (noise < -HCSR04_NOISE_CLIP_SD) noise = -HCSR04_NOISE_CLIP_SD;
  const double cm = (distance_m + HCSR04_NOISE_SD_M * noise) * 100.0;
  return (int64_t)llround(cm * (double)HCSR04_ECHO_NS_PER_CM);
}

void hcsr04_trigger(struct hcsr04 *s, int level, int64_t t_ns) {
  level = level != 0;
  if (level == s->trig_level) return;
  s->trig_level = level;
  if (level) {
    s->trig_rise_ns = t_ns;
    return;
  }
  if (t_ns - s->trig_rise_ns < HCSR04_TRIG_MIN_NS) return; /* too short to be seen */
  if (s->last_start_ns != INT64_MIN && t_ns - s->last_start_ns < HCSR04_CYCLE_MIN_NS) return;
  s->last_start_ns = t_ns;
  /* The distance in force when the burst leaves. */
  const int64_t burst_ns = t_ns + HCSR04_ECHO_DELAY_NS - HCSR04_BURST_NS;
  const double d = s->distance_t_ns[1] <= burst_ns ? s->distance_m[1] : s->distance_m[0];
  s->echo_rise_ns = t_ns + HCSR04_ECHO_DELAY_NS;
  s->echo_fall_ns = s->echo_rise_ns + hcsr04_echo_width_ns(d, s->seed, s->measurements);
  s->burst_ns = burst_ns;
  s->burst_measurement = s->measurements;
  s->measurements++;
}

int64_t hcsr04_next_edge_ns(const struct hcsr04 *s) {
  if (s->echo_rise_ns != NONE) return s->echo_rise_ns;
  return s->echo_fall_ns;
}

int hcsr04_take_edge(struct hcsr04 *s) {
  if (s->echo_rise_ns != NONE) {
    s->shown_rise_ns = s->echo_rise_ns;
    s->echo_rise_ns = NONE;
    s->echo_level = 1;
  } else if (s->echo_fall_ns != NONE) {
    s->last_width_ns = s->echo_fall_ns - s->shown_rise_ns;
    s->echo_fall_ns = NONE;
    s->echo_level = 0;
  }
  return s->echo_level;
}

int64_t hcsr04_last_echo_width_ns(const struct hcsr04 *s) { return s->last_width_ns; }
