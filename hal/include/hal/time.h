/* Time since hal_init(): milliseconds and microseconds (both wrap around), and blocking delays.
 * Interrupts still run during a delay. */
#ifndef SEAR_HAL_TIME_H
#define SEAR_HAL_TIME_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

uint32_t millis(void); /* wraps after 49.7 days */
uint32_t micros(void); /* wraps after 71.6 minutes */
void delay_ms(uint32_t ms);
void delay_us(uint32_t us);

#ifdef __cplusplus
}
#endif
#endif
