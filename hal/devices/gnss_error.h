/* The error of a single-frequency hobby GPS receiver, world-free: time-correlated (first-order
 * Gauss-Markov) position error in metres, white velocity noise, time to first fix, and a fixed sky
 * whose satellite count and DOPs agree with the configured accuracy. Every draw comes from
 * noise.h indexed by a 100 ms tick, so a tick's error is the same whatever was asked before. */
#ifndef SEAR_DEVICES_GNSS_ERROR_H
#define SEAR_DEVICES_GNSS_ERROR_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The error process runs on this grid whatever the output rate (10 Hz is the fastest rate either
 * talker offers), so changing the rate never changes the error at a given time. */
/* What a talker asks of the world at a measurement epoch: the antenna's true position and
 * velocity (velocity in the local east-north-up frame at that position). */
struct gnss_fix_truth {
  int64_t time_ns;
  double latitude_deg, longitude_deg, altitude_msl_m, geoid_separation_m, east_mps, north_mps, up_mps;
};
/* The talker asks only at its measurement epochs, i.e. only for fixes that will be sent. */
struct gnss_truth_source {
  void (*fix_at)(void *context, int64_t time_ns, struct gnss_fix_truth *out);
  void *context;
};

#define GNSS_ERROR_TICK_NS INT64_C(100000000)

/* For a circular Gaussian with per-axis sigma s the 50 % radius is s * sqrt(2 ln 2). */
#define GNSS_CEP_PER_SIGMA 1.1774100225154747

/* NEO-6 datasheet (GPS.G6-HW-09005), table "GPS performance": horizontal position accuracy
 * 2.5 m CEP (autonomous), velocity accuracy 0.1 m/s, cold start TTFF 27 s. */
#define GNSS_DEFAULT_CEP_M 2.5
#define GNSS_DEFAULT_VELOCITY_SD_MPS 0.1
#define GNSS_DEFAULT_TTFF_S 27.0
/* Not in any datasheet: a correlation time typical of the slowly wandering error of an
 * unaided receiver (ionosphere, multipath, orbit errors change over minutes). */
#define GNSS_DEFAULT_CORRELATION_S 60.0

#define GNSS_SKY_SATELLITES 12
#define GNSS_MIN_USED 4 /* a 3D fix needs four pseudoranges */
/* The user-equivalent range error a receiver with this sky would need to show the configured
 * CEP: the number of satellites used is the one whose HDOP brings the implied UERE closest to
 * this (see gnss_error.c). */
#define GNSS_NOMINAL_UERE_M 3.0

struct gnss_error_config {
  double cep_m;              /* horizontal 50 % radius; <= 0: GNSS_DEFAULT_CEP_M */
  double vertical_sd_m;      /* 1-sigma vertical; <= 0: UERE * VDOP of the used satellites */
  double velocity_sd_mps;    /* 1-sigma per axis (east, north, up); < 0: default; 0: none */
  double correlation_s;      /* Gauss-Markov time constant, 0.1 s ... 10000 s; <= 0: default */
  double ttff_s;             /* time to first fix from power-on (or restart); < 0: default */
  uint64_t seed;
};

struct gnss_sky_satellite {
  int prn, elevation_deg, azimuth_deg, snr_dbhz;
};

struct gnss_error {
  struct gnss_error_config config;   /* with defaults filled in */
  double sigma_horizontal_m;         /* per axis */
  double sigma_vertical_m;
  double uere_m;                     /* implied user-equivalent range error */
  int used_count;                    /* the first used_count of gnss_error_sky() */
  double pdop, hdop, vdop;           /* of those satellites */
  /* Gauss-Markov on the tick grid as a truncated moving sum of white draws (see .c). */
  double phi, weight, phi_window;
  int64_t window;
  int64_t cached_tick;               /* -1: nothing cached */
  double cached_sum[3];
};

/* Fills defaults into c: every field as the NEO-6 datasheet, seed 0. */
void gnss_error_defaults(struct gnss_error_config *c);
void gnss_error_init(struct gnss_error *m, const struct gnss_error_config *c);

/* The fixed sky, highest first; the receiver uses the first m->used_count. */
const struct gnss_sky_satellite *gnss_error_sky(void);

/* PDOP, HDOP, VDOP of `count` satellites of `sats` (ENU geometry with a clock term); returns 0 if
 * the geometry is singular. */
int gnss_dop(const struct gnss_sky_satellite *sats, int count, double *pdop, double *hdop, double *vdop);

struct gnss_error_sample {
  double east_m, north_m, up_m;          /* position error */
  double east_mps, north_mps, up_mps;    /* velocity error */
};

/* The error at the tick containing `since_power_on_ns` (>= 0). */
void gnss_error_at(struct gnss_error *m, int64_t since_power_on_ns, struct gnss_error_sample *out);

/* 1 once `since_start_ns` (from power-on or a restart) has reached the time to first fix. */
int gnss_error_has_fix(const struct gnss_error *m, int64_t since_start_ns);
/* How many of the sky's satellites are tracked `since_start_ns` after a start: the first after
 * GNSS_FIRST_ACQUISITION_S, one more every GNSS_ACQUISITION_STEP_S, all of them at the fix (a
 * cold start spends most of its TTFF decoding ephemerides of satellites already tracked). */
#define GNSS_FIRST_ACQUISITION_S 2.0 /* assumption; real logs show an empty GSV in the first second */
#define GNSS_ACQUISITION_STEP_S 0.5  /* assumption */
int gnss_error_tracked(const struct gnss_error *m, int64_t since_start_ns);

/* Moves a WGS-84 point by east/north/up metres (radii of curvature at the point; the
 * linearisation error is below 1e-6 m for offsets of tens of metres). */
void gnss_offset_position(double *latitude_deg, double *longitude_deg, double *height_m, double east_m,
                          double north_m, double up_m);

#ifdef __cplusplus
}
#endif
#endif
