/* The firmware's clock: its virtual time, which only HAL calls and delays move. */
#include <hal/time.h>

#include "mcu.h"

uint32_t millis(void) { return (uint32_t)(mcu_enter(SEAR_CALL_millis) / 1000000); }

uint32_t micros(void) { return (uint32_t)(mcu_enter(SEAR_CALL_micros) / 1000); }

/* A delay lasts exactly what it asks, without the cost of the call itself. */
void delay_ms(uint32_t ms) {
  const int64_t now = mcu_enter(SEAR_CALL_delay_ms);
  mcu_advance_to(now + (int64_t)ms * 1000000);
}

void delay_us(uint32_t us) {
  const int64_t now = mcu_enter(SEAR_CALL_delay_us);
  mcu_advance_to(now + (int64_t)us * 1000);
}
