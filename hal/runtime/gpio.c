/* Digital pins as the firmware drives and reads them. */
#include <hal/gpio.h>

#include "mcu.h"

void pin_mode(uint8_t pin, uint8_t mode) {
  const int64_t now = mcu_enter(SEAR_CALL_pin_mode);
  mcu_check_pin(pin, "pin_mode");
  if (mode > INPUT_PULLUP) mcu_fatal("pin_mode(%u, %u): mode must be INPUT, OUTPUT or INPUT_PULLUP", pin, mode);
  if (mode == INPUT) sear_mcu.latch[pin] = LOW;
  if (mode == INPUT_PULLUP) sear_mcu.latch[pin] = HIGH;
  if (mode == OUTPUT) sear_mcu.ever_output[pin] = 1;
  if (sear_mcu.mode[pin] == mode) return;
  const int was_output = sear_mcu.mode[pin] == OUTPUT;
  sear_mcu.mode[pin] = mode;
  sear_mcu.pwm[pin] = 0;
  mcu_emit(SEAR_EVENT_PIN_MODE, pin, mode, now);
  if (mode == OUTPUT) {
    mcu_emit(SEAR_EVENT_PIN, pin, sear_mcu.latch[pin], now);
    mcu_devices_pin_written(pin, sear_mcu.latch[pin], now);
  } else if (was_output) {
    /* Let go: a device on the line (a chip select) now sees what the pull-up or nothing gives. */
    mcu_devices_pin_written(pin, mcu_pin_level(pin), now);
  }
}

uint8_t digital_read(uint8_t pin) {
  mcu_enter(SEAR_CALL_digital_read);
  mcu_check_pin(pin, "digital_read");
  sear_mcu.link->usage.pin_read[pin] = 1;
  return mcu_pin_level(pin);
}

void mcu_drive_latch(uint8_t pin, uint8_t level, int64_t now) {
  const uint8_t was = mcu_pin_level(pin);
  const int was_pwm = sear_mcu.pwm[pin];
  struct sear_link_usage *usage = &sear_mcu.link->usage;
  if (!sear_mcu.ever_output[pin] && !usage->input_write[pin]) { /* for the run's report: it only moved the pull-up */
    usage->input_write[pin] = (uint8_t)(1 + level);
    usage->input_write_ns[pin] = now;
  }
  sear_mcu.latch[pin] = level;
  sear_mcu.pwm[pin] = 0; /* as on the chip's timer pins: a digital write ends the PWM waveform */
  if (sear_mcu.mode[pin] == OUTPUT && (was != level || was_pwm)) {
    mcu_emit(SEAR_EVENT_PIN, pin, level, now);
    mcu_devices_pin_written(pin, level, now);
  }
}

void digital_write(uint8_t pin, uint8_t level) {
  const int64_t now = mcu_enter(SEAR_CALL_digital_write);
  mcu_check_pin(pin, "digital_write");
  mcu_drive_latch(pin, level ? HIGH : LOW, now);
}

void digital_toggle(uint8_t pin) {
  const int64_t now = mcu_enter(SEAR_CALL_digital_toggle);
  mcu_check_pin(pin, "digital_toggle");
  mcu_drive_latch(pin, sear_mcu.latch[pin] ? LOW : HIGH, now);
}
