/* Digital pins, numbered as printed on an Arduino Mega 2560 board: 0..69, where A0..A15 are
 * 54..69. Inputs may enable the internal pull-up resistor. */
#ifndef SEAR_HAL_GPIO_H
#define SEAR_HAL_GPIO_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HAL_PIN_COUNT 70

#define LOW 0
#define HIGH 1

#define INPUT 0
#define OUTPUT 1
#define INPUT_PULLUP 2

#define A0 54
#define A1 55
#define A2 56
#define A3 57
#define A4 58
#define A5 59
#define A6 60
#define A7 61
#define A8 62
#define A9 63
#define A10 64
#define A11 65
#define A12 66
#define A13 67
#define A14 68
#define A15 69

void pin_mode(uint8_t pin, uint8_t mode);  /* INPUT, OUTPUT or INPUT_PULLUP */
uint8_t digital_read(uint8_t pin);         /* LOW or HIGH */
void digital_write(uint8_t pin, uint8_t level);
void digital_toggle(uint8_t pin);

#ifdef __cplusplus
}
#endif
#endif
