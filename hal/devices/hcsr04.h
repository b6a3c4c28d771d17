/* HC-SR04 ultrasonic ranger (2 cm - 4 m): TRIG pulses in, ECHO pulse out whose width is the
 * sound's round trip, with exact sub-quantum edge times. Distances in metres, times in integer
 * nanoseconds of simulated time. */
#ifndef SEAR_DEVICES_HCSR04_H
#define SEAR_DEVICES_HCSR04_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Datasheet (ElecFreaks "Ultrasonic Ranging Module HC-SR04", "Electric Parameter" table and
 * "Timing diagram"): range 2 cm - 4 m, trigger input a >= 10 us TTL pulse, an 8-cycle 40 kHz
 * burst, "uS / 58 = centimeters", ranging accuracy 3 mm, "we suggest to use over 60ms
 * measurement cycle". */
#define HCSR04_MIN_RANGE_M 0.02
#define HCSR04_MAX_RANGE_M 4.0
#define HCSR04_TRIG_MIN_NS INT64_C(10000)
#define HCSR04_ECHO_NS_PER_CM INT64_C(58000)
#define HCSR04_CYCLE_MIN_NS INT64_C(60000000)
/* 58 us per cm of range is a round trip of 2 cm in 58 us: c = 344.83 m/s, dry air at 22.8 C by
 * c = 331.3 m/s * sqrt(1 + T / 273.15 K). The model uses exactly this speed, so firmware that
 * divides by 58 reads the true distance. */
#define HCSR04_SOUND_SPEED_MPS (0.02 / 58e-6)
/* Burst: 8 cycles at 40 kHz = 200 us. Trigger fall to ECHO rise: 468 us, the fixed delay
 * measured on a module whatever the range (151.80.140.85/hc-sr04.html, "The time from the
 * trigger pulse to the echo pulse is ALWAYS 468USec"): the 200 us burst plus the module's own
 * set-up. */
#define HCSR04_BURST_NS INT64_C(200000)
#define HCSR04_ECHO_DELAY_NS INT64_C(468000)
/* No echo: ECHO drops after its ~38 ms time-out (module notes, "If no echo is received the
 * 'Echo' output will go LOW after 38ms"). The model gives that for nothing within 4 m (the
 * datasheet's maximum; farther echoes are too weak to count on) and for targets closer than
 * 2 cm, whose echo comes back while the receiver still hears the burst's ringing (users report
 * readings below 2-3 cm erratic or missing; we take the part's documented behaviour for a
 * missed echo rather than inventing an erratic value). */
#define HCSR04_NO_ECHO_NS INT64_C(38000000)
/* Per-measurement range noise, Gaussian, standard deviation 1 mm, clipped at 3 sd so no reading
 * is further off than the datasheet's 3 mm accuracy. */
#define HCSR04_NOISE_SD_M 0.001
#define HCSR04_NOISE_CLIP_SD 3.0

struct hcsr04 {
  uint64_t seed;
  uint64_t measurements;        /* measurements started: the noise index of the next one */
  double distance_m[2];         /* [0] the previous, [1] the latest distance given */
  int64_t distance_t_ns[2];
  int trig_level;
  int64_t trig_rise_ns;
  int64_t last_start_ns;        /* last accepted trigger fall, INT64_MIN before any */
  int echo_level;
  int64_t echo_rise_ns;         /* INT64_MAX when none pending */
  int64_t echo_fall_ns;
  int64_t burst_ns;             /* the pending measurement's burst, while ECHO has not risen */
  uint64_t burst_measurement;   /* and its noise index */
  int64_t shown_rise_ns;        /* the latest ECHO rise taken */
  int64_t last_width_ns;        /* the latest complete ECHO pulse's width, -1 before one */
};

void hcsr04_init(struct hcsr04 *s, uint64_t seed);
/* The distance to the target at t_ns; INFINITY (or NaN, or a negative) means nothing answers.
 * A measurement takes the latest distance stamped at or before its burst (which leaves 268 us
 * after TRIG falls), even one given after the trigger, as long as ECHO has not risen yet. The
 * caller gives distances in time order. */
void hcsr04_set_distance(struct hcsr04 *s, double distance_m, int64_t t_ns);
/* The firmware's TRIG level from t_ns on. A fall after >= 10 us high starts a measurement,
 * unless one started less than 60 ms before (ignored, as the module is still busy). */
void hcsr04_trigger(struct hcsr04 *s, int level, int64_t t_ns);
/* Time of the next ECHO edge, INT64_MAX when none is pending. */
int64_t hcsr04_next_edge_ns(const struct hcsr04 *s);
/* Applies the next ECHO edge and returns the new level (1 high, 0 low). */
int hcsr04_take_edge(struct hcsr04 *s);
/* Width of the ECHO pulse for a target at distance_m with the given noise draw: 58 us per cm in
 * 2 cm - 4 m, HCSR04_NO_ECHO_NS outside. Exposed so tests and tools compute what a measurement
 * gives. */
int64_t hcsr04_echo_width_ns(double distance_m, uint64_t seed, uint64_t measurement);
/* The width of the latest ECHO pulse that ended (what a firmware timing it gets), -1 before the
 * first. */
int64_t hcsr04_last_echo_width_ns(const struct hcsr04 *s);

#ifdef __cplusplus
}
#endif
#endif
