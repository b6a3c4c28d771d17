/* Arduino Mega pin numbers (0..69) to ATmega2560 port registers and timer output channels;
 * internal to the AVR target. */
#ifndef SEAR_HAL_AVR_PIN_MAP_H
#define SEAR_HAL_AVR_PIN_MAP_H

#include <stdint.h>

/* A pin's three port registers. Every port of the 2560 has PINx, DDRx and PORTx at consecutive
 * addresses (datasheet, Register Summary), so one address is enough to reach all three. Three
 * bytes, so it comes back from hal_avr_pin_io in registers. */
typedef struct {
    volatile uint8_t *pin; /* PINx; DDRx is pin[1], PORTx is pin[2] */
    uint8_t mask;          /* the pin's bit within the port; 0 for a pin that does not exist */
} pin_io;

#define PIN_IN(io) ((io).pin[0])
#define PIN_DDR(io) ((io).pin[1])
#define PIN_PORT(io) ((io).pin[2])

/* The registers of pins 0..69; mask 0 for any other number. */
pin_io hal_avr_pin_io(uint8_t pin);

/* The timer output compare channel wired to a pin: timer number (0..5) in the high nibble,
 * channel (0 = A, 1 = B, 2 = C) in the low one; PIN_NO_TIMER for pins without one. */
#define PIN_NO_TIMER 0xFF
#define PIN_TIMER_NUMBER(code) ((uint8_t)((code) >> 4))
#define PIN_TIMER_CHANNEL(code) ((uint8_t)((code) & 0x0F))
uint8_t hal_avr_pin_timer(uint8_t pin);

/* Disconnects the pin's timer channel so that PORTx drives the pin again (a digital write after
 * pwm_write or servo_write_us must win, as on an Arduino). */
void hal_avr_pin_timer_off(uint8_t pin);

#endif
