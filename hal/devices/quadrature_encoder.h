/* Incremental quadrature encoder on a wheel shaft: channels A and B, 90 degrees apart, A leading
 * B when turning forward, with each edge at the exact time the shaft crosses it. Angles in rad,
 * rates in rad/s, times in integer nanoseconds. */
#ifndef SEAR_DEVICES_QUADRATURE_ENCODER_H
#define SEAR_DEVICES_QUADRATURE_ENCODER_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* counts_per_rev is cycles per revolution of each channel (the "CPR"/"PPR" of encoder catalogues);
 * a decoder counting every edge of both channels ("x4") gets 4 * counts_per_rev per revolution.
 * The shaft angle splits into quarter cycles; quarter n = floor(angle / (2 pi / (4 cpr))) has
 * (A, B) = (0,0), (1,0), (1,1), (0,1) for n mod 4 = 0, 1, 2, 3: forward, A rises a quarter
 * cycle before B. */
struct quadrature_encoder {
  uint32_t counts_per_rev;
  double quarter_rad;       /* angle between edges */
  int64_t shown_quarter;    /* the quarter whose levels the pins show now */
  int64_t motion_t_ns;      /* the motion given last: angle at that time, constant rate */
  double motion_angle_rad;
  double motion_rate_radps;
  int64_t motion_quarter;   /* the quarter of motion_angle_rad */
  int catching_up;          /* shown_quarter still walking to motion_quarter, at motion_t_ns */
};

/* angle_rad is where the shaft is at power-up (0 is a quarter boundary of A rising). */
void encoder_init(struct quadrature_encoder *s, uint32_t counts_per_rev, double angle_rad);
/* The shaft at angle_rad (continuous, never wrapped) at t_ns, turning at rate_radps until the next
 * call. Quarters the shaft passed that have not been shown yet come out as edges at t_ns, so no
 * count is ever lost; the motion's edges follow at their crossing times. */
void encoder_set_motion(struct quadrature_encoder *s, double angle_rad, double rate_radps, int64_t t_ns);
/* Time of the next edge on either channel, INT64_MAX when the shaft stands still. */
int64_t encoder_next_edge_ns(const struct quadrature_encoder *s);
/* Applies the next edge (call only while next_edge_ns is not INT64_MAX): which channel moved
 * (0 = A, 1 = B) and its new level. Exactly one channel changes per edge, as on the part. */
void encoder_take_edge(struct quadrature_encoder *s, int *channel, int *level);
/* Levels shown now: bit 0 = A, bit 1 = B. */
int encoder_levels(const struct quadrature_encoder *s);
/* The quarter the pins show, counted from angle 0: what an x4 decoder counting every edge reads
 * (signed, 4 per cycle) when powered up at angle 0, and the angle that count means. */
int64_t encoder_count(const struct quadrature_encoder *s);
double encoder_count_angle_rad(const struct quadrature_encoder *s);

#ifdef __cplusplus
}
#endif
#endif
