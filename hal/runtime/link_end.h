/* The firmware's end of the lockstep link: attaching to the memory the simulator shares, handing
 * the turn back and forth, and the event queue towards the simulator. */
#ifndef SEAR_HAL_RUNTIME_LINK_END_H
#define SEAR_HAL_RUNTIME_LINK_END_H

#include <stdint.h>

#include "lockstep_link.h"

/* Maps the link named in the environment, checks it is this runtime's layout, and sets up
 * sear_mcu.link; exits the process with a message if it cannot. */
void mcu_link_attach(void);

/* Waits for the first turn, which the simulator gives once the first quantum is ready. */
void mcu_link_first_turn(void);

/* The clock reached the quantum's end: hands the turn back and waits for the next quantum. */
void mcu_link_exchange(void);

void mcu_emit(enum sear_event_kind kind, uint8_t index, uint32_t value, int64_t time_ns);

/* A call the real chip could not do: the run reports `message` and this MCU stops. */
void mcu_fatal(const char *format, ...) __attribute__((noreturn, format(printf, 1, 2)));

#endif
