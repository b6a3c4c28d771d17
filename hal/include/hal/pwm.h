/* Pulse-width modulation on the timer pins (2..13 and 44..46 on a Mega) and hobby-servo pulses
 * (50 Hz frame): in the simulator on any pin, as Arduino's Servo library makes them from a
 * timer's interrupt; hal/targets/avr makes them in hardware on the 16-bit timer pins 2, 3, 5, 6,
 * 7, 8, 11, 12, 44, 45, 46 only. */
#ifndef SEAR_HAL_PWM_H
#define SEAR_HAL_PWM_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* duty 0 (always low) .. 255 (always high); the pin becomes an output. */
void pwm_write(uint8_t pin, uint8_t duty);

/* A servo pulse of pulse_us microseconds every 20 ms; 0 stops the pulses. */
void servo_write_us(uint8_t pin, uint16_t pulse_us);

#ifdef __cplusplus
}
#endif
#endif
