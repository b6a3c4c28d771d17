/* What the u-blox and MediaTek GPS talkers share: a power-up message, then measurement epochs on
 * the UTC grid of the fix interval, run as the caller's time passes; and the host's command lines
 * taken byte by byte. Each talker supplies its own messages and commands. */
#ifndef SEAR_DEVICES_GNSS_TALKER_H
#define SEAR_DEVICES_GNSS_TALKER_H

#include <stddef.h>
#include <stdint.h>

#include "nmea.h"
#include "serial_byte.h"

#ifdef __cplusplus
extern "C" {
#endif

struct gnss_talker {
  int64_t power_on_ns;
  int64_t start_ns;       /* power-on or the last restart (MTK), from which the first fix takes its time */
  int64_t boot_ns;        /* power-on to the power-up message */
  int64_t utc_start_ms;   /* UTC at power-on */
  int64_t period_ms;      /* fix interval (u-blox CFG-RATE measRate, MTK PMTK220) */
  int64_t next_epoch_ms;  /* UTC of the next measurement */
  uint64_t epoch_count;   /* epochs run so far */
  int booted;             /* the power-up message has been queued */
  /* Optional, set after init (NULL: none): runs output_delay_ns after each epoch. A talker that
   * has it takes its measurement in the epoch event and queues the messages here, so that
   * answers to commands that arrive in between leave first, as from a receiver still computing
   * its solution. Called with the talker pointer the events get. */
  void (*output)(void *talker);
  int64_t output_delay_ns;
  int output_pending;     /* an output event is still to run, at output_ns */
  int64_t output_ns;
};

/* A talker's two events. The talker is passed back as the void pointer. */
struct gnss_talker_events {
  void (*boot)(void *talker);   /* queues the power-up message, at power_on_ns + boot_ns */
  void (*epoch)(void *talker);  /* queues the sentences of the epoch at next_epoch_ms */
};

/* rate_hz is clamped to 1 ... 10 Hz (a NaN to 1); the first epoch is the first on the grid after
 * the power-up message. */
void gnss_talker_init(struct gnss_talker *g, int64_t power_on_ns, int64_t boot_ns, int64_t utc_start_s,
                      double rate_hz);
/* Simulation time of the epoch at UTC utc_ms. */
int64_t gnss_talker_epoch_ns(const struct gnss_talker *g, int64_t utc_ms);
/* A new fix interval set by a command at t_ns: epochs go on from the new grid's next point after
 * t_ns (or after the power-up message, if that is still to come). */
void gnss_talker_set_period(struct gnss_talker *g, int64_t period_ms, int64_t t_ns);
/* 1 if a message output every rate-th epoch (0: off) is due in the epoch being run. */
int gnss_talker_due(const struct gnss_talker *g, uint8_t rate);

/* Runs every event at or before t_ns: what the module did up to a host's byte comes first, so an
 * answer follows the output already on the line. */
void gnss_talker_catch_up(struct gnss_talker *g, const struct gnss_talker_events *ev, void *talker, int64_t t_ns);
/* The talker's transmit call (see ublox_neo6m_transmit): runs the events before until_ns as the
 * bytes already queued in tx leave. */
size_t gnss_talker_transmit(struct gnss_talker *g, const struct gnss_talker_events *ev, void *talker,
                            struct nmea_tx *tx, int64_t now_ns, int64_t until_ns, struct serial_byte *out,
                            size_t cap);

/* 1 if baud is one of the count rates in bauds. */
int gnss_baud_listed(const uint32_t *bauds, size_t count, uint32_t baud);

/* Adds one host byte c to line (*len bytes held, room for max): '$' starts a line over, and one
 * that outgrows max is dropped, so the next '$' resyncs. At the LF that ends a well-framed
 * sentence, copies its body (between '$' and '*') NUL-terminated into body (room for max) and
 * returns the body's length; otherwise, or for an empty body, returns 0. */
size_t gnss_line_byte(char *line, size_t *len, size_t max, char c, char *body);
/* Splits body at commas into at most max fields, in place; returns how many. */
int gnss_split_fields(char *body, char **fields, int max);

#ifdef __cplusplus
}
#endif
#endif
