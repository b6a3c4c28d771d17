/* The check for loops that wait for an interrupt without calling the HAL, and for the endless empty
 * loop that halts the MCU (idle.c). */
#ifndef SEAR_HAL_RUNTIME_IDLE_H
#define SEAR_HAL_RUNTIME_IDLE_H

/* Starts the check, at hal_init(): a loop that waits can end once an interrupt handler is
 * attached, and `while (true);` halts the MCU with or without one. */
void mcu_watch_idle_loops(void);

#endif
