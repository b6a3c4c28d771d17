/* Start-up: call hal_init() first thing in main(), before any other HAL call. It brings the
 * clock, timers, ADC and interrupts to the state the rest of the HAL expects. */
#ifndef SEAR_HAL_SYSTEM_H
#define SEAR_HAL_SYSTEM_H

#ifdef __cplusplus
extern "C" {
#endif

void hal_init(void);
/* Stops this MCU with `message`, reported as the HAL's own refusals are (the run names the MCU,
 * the sim time and the last call): for layers on the HAL, such as hal/arduino, that meet
 * something they cannot model. On the real chip it halts with interrupts off. */
void hal_refuse(const char *message) __attribute__((noreturn));

#ifdef __cplusplus
}
#endif
#endif
