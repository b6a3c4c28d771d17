/* What each pin of the reference board (Arduino Mega 2560) can do, so that the simulator refuses
 * what the real chip could not do instead of letting it work only here. */
#ifndef SEAR_HAL_RUNTIME_BOARD_H
#define SEAR_HAL_RUNTIME_BOARD_H

#include <stdint.h>

int board_has_pwm(uint8_t pin);       /* timer output compare pins */
int board_has_servo(uint8_t pin);     /* 16-bit timer output compare pins */
int board_has_interrupt(uint8_t pin); /* INT0..5 and PCINT pins */
int board_has_pin_change(uint8_t pin); /* PCINT pins: 10..15, 50..53, A8..A15 */

#endif
