/* MaxBotix LV-MaxSonar-EZ1 (MB1010) sonar: the same reading on three outputs at once, analog
 * (AN), pulse width (PW) and RS-232-polarity serial (TX), every 49 ms, with the RX pin's stop.
 * Distances in metres, times in integer nanoseconds since power-up. */
#ifndef SEAR_DEVICES_MAXBOTIX_LV_EZ_H
#define SEAR_DEVICES_MAXBOTIX_LV_EZ_H

#include <stddef.h>
#include <stdint.h>

#include "serial_byte.h"

#ifdef __cplusplus
extern "C" {
#endif

/* LV-MaxSonar-EZ1 Data Sheet (MaxBotix), numbers by section:
 *  - front page: range information from 6 to 254 inches, 1-inch resolution; "Objects from
 *    0-inches to 6-inches range as 6-inches".
 *  - Pin Out, AN: (Vcc/512) per inch; PW: 147 us per inch; TX: "R", three ASCII digits of inches
 *    "up to a maximum of 255", carriage return, 9600 baud 8N1, "RS232 format, except voltages
 *    are 0-Vcc" (so idle low, bits inverted: "If standard voltage level RS232 is desired,
 *    invert, and connect an RS232 converter such as a MAX232"). RX: internally pulled high; left
 *    open or high the part ranges continually; held low it stops; "Bring high 20uS or more" to
 *    command a reading.
 *  - Timing Description: ready 250 ms after power-up; with RX open/high it first runs a
 *    calibration cycle (49 ms), then a range reading (49 ms); the RX pin is checked at the end
 *    of every cycle. Each cycle: thirteen 42 kHz waves, then PW high; PW low when the target is
 *    detected, high for up to 37.5 ms with no target; the rest of the cycle, less 4.7 ms, is
 *    spent adjusting the analog voltage; serial data is sent during the last 4.7 ms. */
#define MAXBOTIX_MIN_INCHES 6
#define MAXBOTIX_MAX_INCHES 254
#define MAXBOTIX_NO_TARGET_INCHES 255  /* PW held the full 37.5 ms = 255 x 147 us; serial max */
#define MAXBOTIX_PW_NS_PER_INCH INT64_C(147000)
#define MAXBOTIX_AN_STEPS_PER_VCC 512.0
#define MAXBOTIX_BAUD 9600u
#define MAXBOTIX_SERIAL_INVERTED 1     /* TX is RS-232 polarity at logic levels */
#define MAXBOTIX_POWER_UP_NS INT64_C(250000000)
#define MAXBOTIX_CYCLE_NS INT64_C(49000000)
#define MAXBOTIX_RX_COMMAND_NS INT64_C(20000)
#define MAXBOTIX_PW_RISE_NS INT64_C(309524)      /* 13 waves at 42 kHz = 309.52 us */
#define MAXBOTIX_LISTEN_NS INT64_C(37500000)     /* PW high at most 37.5 ms */
#define MAXBOTIX_SERIAL_START_NS (MAXBOTIX_CYCLE_NS - INT64_C(4700000))
/* The datasheet's own 4.7 ms is shorter than five 9600-baud frames (5.21 ms): the model starts
 * the first start bit 4.7 ms before the cycle's end, as written, and lets the carriage return
 * finish 0.51 ms into the next cycle (while that cycle is still in its burst). The analog output
 * moves from the previous reading to the new one between the end of listening (PW's latest
 * possible fall) and the start of the serial data, linearly (the datasheet only says it is
 * "spent adjusting"). Before the first reading it is 0 V (assumption: nothing in the buffer). */
#define MAXBOTIX_AN_RAMP_START_NS (MAXBOTIX_PW_RISE_NS + MAXBOTIX_LISTEN_NS)
#define MAXBOTIX_AN_RAMP_END_NS MAXBOTIX_SERIAL_START_NS
/* Per-reading range noise, Gaussian, standard deviation 0.25 inch (6.35 mm) before quantising
 * to whole inches: a still target then reads steady, with the occasional one-inch flicker of a
 * real part near an inch boundary (assumption; the datasheet gives resolution, not noise). */
#define MAXBOTIX_NOISE_SD_M 0.00635

/* The reading of cycle k: the distance in inches plus noise drawn from (seed, k), truncated to
 * whole inches (the part counts whole 147 us steps), clamped to 6..254; INFINITY, NaN or a
 * negative distance, or anything beyond 254 in, gives MAXBOTIX_NO_TARGET_INCHES. Both the
 * in-firmware outputs and the serial device call this, so cycle k reads the same on all three. */
int maxbotix_reading_inches(double distance_m, uint64_t seed, uint64_t k, double noise_sd_m);
/* Start of cycle k when free-running from power-up (RX open): 250 ms + one calibration cycle
 * + k cycles. */
int64_t maxbotix_cycle_start_ns(uint64_t k);
/* "R", three digits, CR for `inches` (0..255, clamped); returns 5. */
size_t maxbotix_serial_frame(int inches, uint8_t out[5]);

/* When the next cycle starts, given the RX pin: shared by both halves so they agree on the
 * cycles whatever the firmware does with RX. The caller gives RX edges in time order, and every
 * edge before a cycle's start before it takes that cycle. */
struct maxbotix_schedule {
  int64_t boundary_ns;   /* end of the last cycle: the next may start here if RX is high */
  int64_t rx_rise_ns;    /* last low-to-high RX edge (0: pulled high from power-up) */
  int rx_level;
  int calibrated;        /* the calibration cycle has run */
  uint64_t next_k;
};
void maxbotix_schedule_init(struct maxbotix_schedule *c);
void maxbotix_schedule_set_rx(struct maxbotix_schedule *c, int level, int64_t t_ns);
/* Start of the next ranging cycle (its k in *k if not NULL), INT64_MAX while stopped by RX. */
int64_t maxbotix_schedule_next_ns(const struct maxbotix_schedule *c, uint64_t *k);
/* Moves past the cycle next_ns returned. */
void maxbotix_schedule_take(struct maxbotix_schedule *c);

/* The outputs the firmware's process serves: PW as edges, AN as volts. */
struct maxbotix_lv_ez {
  struct maxbotix_schedule schedule;
  int pw_level;
  int64_t pw_rise_ns, pw_fall_ns;  /* INT64_MAX when not pending */
  int an_from_inches, an_to_inches; /* analog ramps from one to the other ... */
  int64_t an_ramp_start_ns, an_ramp_end_ns; /* ... over this span */
};
void maxbotix_lv_ez_init(struct maxbotix_lv_ez *s);
void maxbotix_lv_ez_set_rx_level(struct maxbotix_lv_ez *s, int level, int64_t t_ns);
/* Start of the next cycle (and its k), INT64_MAX while RX holds the part stopped. */
int64_t maxbotix_lv_ez_next_cycle_ns(const struct maxbotix_lv_ez *s, uint64_t *k);
/* Runs the cycle starting at t_cycle_ns (the one next_cycle_ns gave) with this reading, from
 * maxbotix_reading_inches(distance at t_cycle_ns, seed, k, noise). */
void maxbotix_lv_ez_take_reading(struct maxbotix_lv_ez *s, int inches, int64_t t_cycle_ns);
int64_t maxbotix_lv_ez_next_edge_ns(const struct maxbotix_lv_ez *s);
int maxbotix_lv_ez_take_edge(struct maxbotix_lv_ez *s); /* the new PW level */
/* AN at t_ns for supply vcc_v (queried at or after the latest reading's cycle start). */
double maxbotix_lv_ez_analog_v(const struct maxbotix_lv_ez *s, int64_t t_ns, double vcc_v);
/* The reading (inches) AN has settled on by t_ns: the latest once its ramp ended, else the one
 * before. */
int maxbotix_lv_ez_shown_inches(const struct maxbotix_lv_ez *s, int64_t t_ns);

/* The TX output, a UART device in the simulator's process: frames out with their times, in the
 * byte values sent; the wire carries them inverted (MAXBOTIX_SERIAL_INVERTED). */
struct maxbotix_lv_ez_serial {
  struct maxbotix_schedule schedule;
  uint64_t seed;
  double noise_sd_m;
  double distance_m;
  int64_t distance_t_ns;
  uint8_t frame[2][5];         /* a frame can still be going out when the next cycle starts */
  int64_t frame_start_ns[2];   /* first start bit; frame[0] goes first */
  int64_t frame_cycle_ns[2];   /* its cycle's start, reading number, and the stamp of the */
  uint64_t frame_k[2];         /* distance it was measured with */
  int64_t frame_distance_t_ns[2];
  int frame_count;
  int next_byte;               /* of frame[0] */
};
void maxbotix_lv_ez_serial_init(struct maxbotix_lv_ez_serial *s, uint64_t seed, double noise_sd_m);
/* The distance to the target at t_ns (INFINITY: nothing). A cycle is measured with the latest
 * distance given when it is taken (by transmit, once it has started); a distance given later but
 * stamped at or before the cycle's start, and newer than the one used, replaces it as long as
 * the cycle's frame has not begun to go out. So the truth for a cycle's start may come before or
 * after the transmit call that covers it, as with the firmware-side half. */
void maxbotix_lv_ez_serial_set_distance(struct maxbotix_lv_ez_serial *s, double distance_m, int64_t t_ns);
void maxbotix_lv_ez_serial_set_rx_level(struct maxbotix_lv_ez_serial *s, int level, int64_t t_ns);
/* Like sim/devices/uart_device.hpp's transmit: the bytes not given yet whose stop bit ends
 * before until_ns, in order, at most cap (the rest come next call); returns how many. Bytes keep
 * the part's own times (a byte in flight at now_ns started before it). Cycles starting before
 * until_ns are measured with the latest distance given. */
size_t maxbotix_lv_ez_serial_transmit(struct maxbotix_lv_ez_serial *s, int64_t now_ns, int64_t until_ns,
                                      struct serial_byte *out, size_t cap);

#ifdef __cplusplus
}
#endif
#endif
