/* Start-up: call hal_init() first thing in main(), before any other HAL call. It brings the
 * clock, timers, ADC and interrupts to the state the rest of the HAL expects. */
#ifndef SEAR_HAL_SYSTEM_H
#define SEAR_HAL_SYSTEM_H

#ifdef __cplusplus
extern "C" {
#endif

void hal_init(void);

#ifdef __cplusplus
}
#endif
#endif
