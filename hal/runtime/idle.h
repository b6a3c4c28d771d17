/* The check for loops that wait for an interrupt without calling the HAL (idle.c). */
#ifndef SEAR_HAL_RUNTIME_IDLE_H
#define SEAR_HAL_RUNTIME_IDLE_H

/* Starts the check once an interrupt handler is attached: only then can such a loop end. */
void mcu_watch_idle_loops(void);

#endif
