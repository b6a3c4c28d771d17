/* Pin levels (see pins.h): the firmware's output latches and the levels devices drive onto its
 * inputs; a level change on an input raises its pin interrupt. And the native side of the board
 * interface the device entries talk to (devices.h). */
#include "pins.h"

#include <hal/gpio.h>

#include "devices.h"
#include "link_end.h"
#include "mcu_state.h"

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
  if (before == after) return;
  sear_mcu.pin_change_ns[pin] = mcu_devices_time_ns();
  if (!sear_mcu.pin_handler[pin]) return;
  if ((after == HIGH && (sear_mcu.pin_edges[pin] & IRQ_RISING)) ||
      (after == LOW && (sear_mcu.pin_edges[pin] & IRQ_FALLING)))
    mcu_set_pin_pending(pin, 1);
}

/* The board interface the device entries talk to (devices.h), for the native engine. A change of
 * what a device drives reaches the simulator too, at the device's own time, for the waveforms. */
void board_drive_pin(uint8_t pin, uint8_t level) {
  if (sear_mcu.driven[pin] != level)
    mcu_emit(SEAR_EVENT_PIN_DRIVEN, pin, level == MCU_FLOATING ? 2u : level, mcu_devices_time_ns());
  mcu_set_driven(pin, level);
}

void board_set_analog(uint8_t channel, double volts) { sear_mcu.analog_v[channel] = volts; }

int board_output_low(uint8_t pin) { return sear_mcu.mode[pin] == OUTPUT && sear_mcu.latch[pin] == LOW; }

/* Brought into the scheduler's next look at once, as a TRIG pulse's echo falls due within the
 * same quantum. */
void board_device_event_at(int64_t t_ns) {
  if (t_ns < sear_mcu.next_due_ns) sear_mcu.next_due_ns = t_ns;
}
