/* Servo pulses on pins with no 16-bit timer channel, made by timer5's compare interrupt as the
 * Arduino Servo library makes them on the Mega; internal to the AVR target. */
#ifndef SEAR_HAL_AVR_SOFT_SERVO_H
#define SEAR_HAL_AVR_SOFT_SERVO_H

#include <avr/io.h>
#include <stdint.h>

/* Up to this many pins at once, each pulsed in turn in one frame (the library's 12 a timer). */
#define SOFT_SERVO_MAX 12

/* 20 ms frames at clk/8 (0.5 us a count): timer5's 16-bit count, running freely. */
#define SOFT_SERVO_FRAME_COUNTS 40000u

/* pulse_us 400..20000 starts or changes the pin's pulses from its next turn in the frame; 0 stops
 * them (the pin stays LOW), and with the last one stopped timer5 goes back to PWM. Refused while
 * irq_timer_start holds timer5, or for a pin beyond the 12th. */
void hal_avr_soft_servo_write(uint8_t pin, uint16_t pulse_us);

/* Timer5 makes software servo pulses (its compare B interrupt is on). Inline, so that asking
 * (irq_timer.c) does not link the pulses' interrupt into a firmware that makes none. */
static inline uint8_t hal_avr_soft_servos_running(void)
{
    return (TIMSK5 & _BV(OCIE5B)) != 0;
}

#endif
