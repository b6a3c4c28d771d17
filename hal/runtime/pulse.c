/* pulse_in(): the pin's level is looked at only when something can have changed it (a device's
 * edge, a sample, a received byte, a timer tick, an interrupt's handler), and the clock jumps
 * straight to the next such moment, so a wait costs no hand-off per loop and the edges it times
 * are the models' own, to the nanosecond. */
#include <hal/gpio.h>
#include <hal/pulse.h>

#include "mcu.h"

/* Runs the clock until the pin reads `level` (1) or `deadline_ns` passes first (0). */
static int wait_for(uint8_t pin, uint8_t level, int64_t deadline_ns) {
  struct sear_link *link = sear_mcu.link;
  for (;;) {
    mcu_service();
    if (mcu_pin_level(pin) == level) return 1;
    if (link->clock_ns >= deadline_ns || sear_mcu.exiting) return 0;
    int64_t next = mcu_earliest_input();
    if (next > deadline_ns) next = deadline_ns;
    if (next > link->quantum_end_ns) next = link->quantum_end_ns;
    if (next > link->clock_ns) link->clock_ns = next;
  }
}

uint32_t pulse_in(uint8_t pin, uint8_t level, uint32_t timeout_us) {
  const int64_t start = mcu_enter(SEAR_CALL_pulse_in);
  mcu_check_pin(pin, "pulse_in");
  sear_mcu.link->usage.pin_read[pin] = 1;
  const uint8_t want = level ? HIGH : LOW;
  const uint8_t other = level ? LOW : HIGH;
  const int64_t deadline = start + (int64_t)timeout_us * 1000;
  sear_mcu.slow_path++;
  uint32_t width_us = 0;
  if (wait_for(pin, other, deadline) && wait_for(pin, want, deadline)) {
    const int64_t began = sear_mcu.link->clock_ns;
    if (wait_for(pin, other, deadline)) width_us = (uint32_t)((sear_mcu.link->clock_ns - began + 500) / 1000);
  }
  sear_mcu.slow_path--;
  return width_us;
}
