/* The firmware side's end of the lockstep link, as both firmware runtimes use it: the native HAL
 * runtime (hal/runtime/link_end.c) and the AVR engine (engines/avr/engine.c). Attaching to the
 * page the simulator shares, waiting for the turn and giving it back, the event queue towards
 * the simulator, and a refusal's text. One link per process. */
#ifndef SEAR_LINK_FIRMWARE_END_H
#define SEAR_LINK_FIRMWARE_END_H

#include <stdarg.h>
#include <stdint.h>

#include "lockstep_link.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Maps the link named in the environment (SEAR_LINK_FD_ENV) and checks its layout. Exits with
 * status 2 after printing `outside_sear` when the process was not started by a simulator,
 * `mismatch` when the layout is not this build's; `who` prefixes a system error. */
struct sear_link *sear_end_attach(const char *who, const char *outside_sear, const char *mismatch);

/* Waits until the simulator gives the turn. A simulator that died without handing it over must
 * not leave this process waiting for ever: once it is gone the process exits with status 3. */
void sear_end_wait_for_turn(struct sear_link *link);

/* Hands the turn to the simulator with `request` (it does not wait for it to come back). */
void sear_end_give(struct sear_link *link, enum sear_request request);

/* Whether the event queue is full: hand over with SEAR_REQUEST_DRAIN before the next event. */
static inline int sear_end_events_full(const struct sear_link *link) {
  return link->event_count >= SEAR_LINK_MAX_EVENTS;
}

/* Appends an event; the queue must have room. Published only once written, so a crash right
 * after leaves no half event behind. */
void sear_end_push_event(struct sear_link *link, enum sear_event_kind kind, uint8_t index, uint32_t value,
                         int64_t time_ns);

/* Writes what the run is to report for a refusal into the link; give SEAR_REQUEST_FATAL next. */
void sear_end_set_fatal(struct sear_link *link, const char *format, va_list args);

#ifdef __cplusplus
}
#endif
#endif
