/* Pulse measurement: how long a pin stays at a level, as Arduino's pulseIn() gives it (an HC-SR04's
 * echo, a receiver's servo pulse). The simulator times it exactly against the modelled edges. */
#ifndef SEAR_HAL_PULSE_H
#define SEAR_HAL_PULSE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Waits for any pulse at `level` already under way to end, then for the pin to go to `level`,
 * then for it to leave it; returns the pulse's width in microseconds (rounded to the nearest), or
 * 0 when timeout_us (counted from the call) runs out first. Interrupts run meanwhile. */
uint32_t pulse_in(uint8_t pin, uint8_t level, uint32_t timeout_us);

#ifdef __cplusplus
}
#endif
#endif
