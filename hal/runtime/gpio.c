/* Digital pins: the firmware's output latches and the levels devices drive onto its inputs; a
 * level change on an input raises its pin interrupt. */
#include <hal/gpio.h>

#include "mcu.h"

void mcu_check_pin(uint8_t pin, const char *call) {
  if (pin >= SEAR_LINK_PINS) mcu_fatal("%s(%u): the ATmega2560 board has pins 0..69", call, pin);
}

/* As in the chip's PORT register, an input's latch is its pull-up: INPUT clears it,
 * INPUT_PULLUP sets it, and digital_write() on an input switches it. */
uint8_t mcu_pin_level(uint8_t pin) {
  if (sear_mcu.mode[pin] == OUTPUT) return sear_mcu.latch[pin];
  if (sear_mcu.driven[pin] != MCU_FLOATING) return sear_mcu.driven[pin];
  /* An input nobody drives reads HIGH through the pull-up; without one it floats, and SEAR reads
   * it LOW rather than the noise a real pin would pick up. */
  return sear_mcu.latch[pin];
}

void mcu_set_driven(uint8_t pin, uint8_t level) {
  const uint8_t before = mcu_pin_level(pin);
  sear_mcu.driven[pin] = level;
  const uint8_t after = mcu_pin_level(pin);
  if (before == after || !sear_mcu.pin_handler[pin]) return;
  if ((after == HIGH && (sear_mcu.pin_edges[pin] & IRQ_RISING)) ||
      (after == LOW && (sear_mcu.pin_edges[pin] & IRQ_FALLING)))
    sear_mcu.pin_pending[pin] = 1;
}

void pin_mode(uint8_t pin, uint8_t mode) {
  const int64_t now = mcu_enter(SEAR_CALL_pin_mode);
  mcu_check_pin(pin, "pin_mode");
  if (mode > INPUT_PULLUP) mcu_fatal("pin_mode(%u, %u): mode must be INPUT, OUTPUT or INPUT_PULLUP", pin, mode);
  if (mode == INPUT) sear_mcu.latch[pin] = LOW;
  if (mode == INPUT_PULLUP) sear_mcu.latch[pin] = HIGH;
  if (sear_mcu.mode[pin] == mode) return;
  sear_mcu.mode[pin] = mode;
  sear_mcu.pwm[pin] = 0;
  mcu_emit(SEAR_EVENT_PIN_MODE, pin, mode, now);
  if (mode == OUTPUT) mcu_emit(SEAR_EVENT_PIN, pin, sear_mcu.latch[pin], now);
}

uint8_t digital_read(uint8_t pin) {
  mcu_enter(SEAR_CALL_digital_read);
  mcu_check_pin(pin, "digital_read");
  return mcu_pin_level(pin);
}

static void drive(uint8_t pin, uint8_t level, int64_t now) {
  const uint8_t was = mcu_pin_level(pin);
  const int was_pwm = sear_mcu.pwm[pin];
  sear_mcu.latch[pin] = level;
  sear_mcu.pwm[pin] = 0; /* as on the chip's timer pins: a digital write ends the PWM waveform */
  if (sear_mcu.mode[pin] == OUTPUT && (was != level || was_pwm)) mcu_emit(SEAR_EVENT_PIN, pin, level, now);
}

void digital_write(uint8_t pin, uint8_t level) {
  const int64_t now = mcu_enter(SEAR_CALL_digital_write);
  mcu_check_pin(pin, "digital_write");
  drive(pin, level ? HIGH : LOW, now);
}

void digital_toggle(uint8_t pin) {
  const int64_t now = mcu_enter(SEAR_CALL_digital_toggle);
  mcu_check_pin(pin, "digital_toggle");
  drive(pin, sear_mcu.latch[pin] ? LOW : HIGH, now);
}
