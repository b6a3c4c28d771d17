/* The simulator's checks on what a firmware left in the shared link: the firmware can overwrite
 * that memory, so no value read there is used before it passes these. */
#ifndef SEAR_LINK_CHECK_H
#define SEAR_LINK_CHECK_H

#include <stddef.h>
#include <stdint.h>

#include "lockstep_link.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What the simulator knows of one firmware between turns, kept in its own memory: the quantum it
 * handed over and the last values that passed, against which the next ones are judged. */
struct sear_link_watch {
  int64_t call_cost_ns;    /* the simulator's own copy of what a HAL call costs */
  int64_t quantum_end_ns;  /* of the quantum handed over */
  int64_t turn_clock_ns;   /* the firmware's clock when the turn was handed over */
  int64_t clock_ns;        /* the last clock that passed */
  uint64_t calls;
  uint32_t last_call;      /* enum sear_call */
  int64_t last_event_ns;   /* of pin, PWM, servo and port-start events, which come in time order */
  int64_t last_driven_ns;  /* of the levels devices drive, which come in time order among themselves */
  int64_t last_tx_ns[SEAR_LINK_UARTS];
  int64_t last_rx_ns[SEAR_LINK_UARTS];
  uint32_t can_data_due;   /* CAN_DATA events still owed by the last CAN_TX (2, 1 or 0) */
  uint32_t halt;           /* enum sear_halt, once reported: it never changes after */
  int64_t halted_ns;
};

/* What the firmware reported when it handed the turn back, once checked. */
struct sear_link_turn {
  uint32_t request;      /* enum sear_request */
  uint32_t event_count;  /* <= SEAR_LINK_MAX_EVENTS */
  int64_t clock_ns;
  uint32_t last_call;
  int32_t exit_code;
  char fatal[sizeof(((struct sear_link *)0)->fatal)]; /* NUL-terminated, printable ASCII */
  uint32_t halt;         /* enum sear_halt */
  int64_t halted_ns;     /* when it halted, within the clock it reached */
};

void sear_link_watch_init(struct sear_link_watch *w, int64_t call_cost_ns);

/* Reads the hand-back of a turn once into `turn` and checks it: guards, request, clock (never
 * backwards, never past the quantum by more than one call), call count, counts and halt (at most
 * once, at a time the clock had reached). `handed_back`
 * is 0 for a firmware that died during its turn, whose request is the previous turn's. Returns 0,
 * or -1 with a sentence naming the first bad field in `why`. */
int sear_link_check_turn(const struct sear_link *link, int handed_back, struct sear_link_watch *w,
                         struct sear_link_turn *turn, char *why, size_t why_size);

/* Copies event i into `out` and checks its kind, index, value and time against the ones before.
 * Returns 0, or -1 with a sentence in `why`. */
int sear_link_check_event(const struct sear_link *link, uint32_t i, struct sear_link_watch *w,
                          struct sear_event *out, char *why, size_t why_size);

/* What the simulator last took of each input's reading (lockstep_link.h, readings[]). */
struct sear_reading_watch {
  uint32_t count[SEAR_LINK_MAX_INPUTS];
  int64_t time_ns[SEAR_LINK_MAX_INPUTS];
};

/* The number of values a reading of input kind `kind` holds, 0 for none. */
uint32_t sear_link_reading_values(uint32_t kind);

/* Copies input i's reading into `out` if its count moved since the last call and checks it: a
 * time within what the firmware's clock (`clock_ns`, already checked) reached and not before the
 * reading taken last, every value finite and plausible for `kind` (the simulator's own copy of
 * the input's kind). Returns 1 for a new reading, 0 for none, -1 with a sentence in `why`. */
int sear_link_check_reading(const struct sear_link *link, uint32_t i, uint32_t kind, int64_t clock_ns,
                            struct sear_reading_watch *w, struct sear_link_reading *out, char *why,
                            size_t why_size);

#ifdef __cplusplus
}
#endif
#endif
