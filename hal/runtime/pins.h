/* Pin levels: what the firmware drives and what devices drive onto its inputs, with the pin
 * interrupts a level change raises. */
#ifndef SEAR_HAL_RUNTIME_PINS_H
#define SEAR_HAL_RUNTIME_PINS_H

#include <stdint.h>

void mcu_check_pin(uint8_t pin, const char *call);
uint8_t mcu_pin_level(uint8_t pin);
/* A device drives `level` onto the pin, or MCU_FLOATING to let go of it. */
void mcu_set_driven(uint8_t pin, uint8_t level);
/* The firmware's output latch set to `level` at now (gpio.c): an output's change goes to the
 * simulator and to the device listening there. */
void mcu_drive_latch(uint8_t pin, uint8_t level, int64_t now);

#endif
