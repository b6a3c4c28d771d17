/* Pin levels: what the firmware drives and what devices drive onto its inputs, with the pin
 * interrupts a level change raises. */
#ifndef SEAR_HAL_RUNTIME_PINS_H
#define SEAR_HAL_RUNTIME_PINS_H

#include <stdint.h>

#include "mcu_state.h"

static inline int mcu_pin_pending(uint8_t pin) { return (int)((sear_mcu.pins_pending[pin >> 6] >> (pin & 63)) & 1u); }

static inline void mcu_set_pin_pending(uint8_t pin, int pending) {
  const uint64_t bit = (uint64_t)1 << (pin & 63);
  if (pending)
    sear_mcu.pins_pending[pin >> 6] |= bit;
  else
    sear_mcu.pins_pending[pin >> 6] &= ~bit;
}

/* The lowest pin with an interrupt pending, first in the chip's vector order; -1: none. */
static inline int mcu_first_pending_pin(void) {
  if (sear_mcu.pins_pending[0]) return __builtin_ctzll(sear_mcu.pins_pending[0]);
  if (sear_mcu.pins_pending[1]) return 64 + __builtin_ctzll(sear_mcu.pins_pending[1]);
  return -1;
}

void mcu_check_pin(uint8_t pin, const char *call);
uint8_t mcu_pin_level(uint8_t pin);
/* A device drives `level` onto the pin, or MCU_FLOATING to let go of it. */
void mcu_set_driven(uint8_t pin, uint8_t level);
/* The firmware's output latch set to `level` at now (gpio.c): an output's change goes to the
 * simulator and to the device listening there. */
void mcu_drive_latch(uint8_t pin, uint8_t level, int64_t now);

#endif
