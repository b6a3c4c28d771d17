/* The firmware's end of the lockstep link (see link_end.h). */
#define _GNU_SOURCE
#include "link_end.h"
#include "startup_memory.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "firmware_end.h"
#include "mcu_state.h"

struct mcu sear_mcu;

static void wait_for_turn(void) {
  sear_end_wait_for_turn(sear_mcu.link);
  mcu_paint_after_wait(); /* its dead frames hold host times */
}

static void hand_over(enum sear_request request) {
  if (sear_mcu.exiting) return; /* the simulator has let go of this MCU */
  sear_mcu.slow_path++;
  sear_end_give(sear_mcu.link, request);
  wait_for_turn();
  sear_mcu.slow_path--;
}

void mcu_link_exchange(void) { hand_over(SEAR_REQUEST_QUANTUM_DONE); }

void mcu_link_first_turn(void) { wait_for_turn(); }

void mcu_emit(enum sear_event_kind kind, uint8_t index, uint32_t value, int64_t time_ns) {
  if (sear_mcu.exiting) return;
  if (sear_end_events_full(sear_mcu.link)) hand_over(SEAR_REQUEST_DRAIN);
  sear_end_push_event(sear_mcu.link, kind, index, value, time_ns);
}

void mcu_fatal(const char *format, ...) {
  struct sear_link *link = sear_mcu.link;
  va_list args;
  va_start(args, format);
  sear_end_set_fatal(link, format, args);
  va_end(args);
  if (sear_mcu.exiting) fprintf(stderr, "sear: after exit(): %s\n", link->fatal); /* nobody reads the link now */
  sear_end_give(link, SEAR_REQUEST_FATAL);
  _exit(70);
}

/* main() returned or exit() was called: tell the simulator at once rather than let it find the
 * process gone at its next check. Destructors may still call the HAL after this; from now on it
 * neither hands over nor reports, so they cannot wait for a turn that never comes. */
static void at_exit(void) {
  /* Later calls work on a private copy, so the report keeps the clock and the call at exit. */
  static struct sear_link after_exit;
  struct sear_link *link = sear_mcu.link;
  after_exit = *link;
  sear_mcu.link = &after_exit;
  sear_mcu.exiting = 1;
  sear_end_give(link, SEAR_REQUEST_EXIT);
}

void mcu_link_attach(void) {
  sear_mcu.link = sear_end_attach("sear",
                                  "This firmware was built for the SEAR simulator: run it through a project, "
                                  "with `sear run PROJECT`.",
                                  "sear: this firmware's HAL runtime does not match the simulator; rebuild it");
  atexit(at_exit);
}
