/* Servo pulses made by hand on pin 30, which has no timer: digital_write and delays, 20 ms
 * frames, 1500 us for the first second, 2000 us for the next, then none. With the HAL's default
 * call cost each HIGH lasts the delay plus one call (3.125 us at 50 cycles, 16 MHz). */
#include <hal/hal.h>

#define PIN 30

static void pulses(uint16_t width_us, uint16_t frames) {
  for (uint16_t i = 0; i < frames; ++i) {
    digital_write(PIN, HIGH);
    delay_us(width_us);
    digital_write(PIN, LOW);
    delay_us(20000u - width_us);
  }
}

int main(void) {
  hal_init();
  pin_mode(PIN, OUTPUT);
  pulses(1500, 50);
  pulses(2000, 50);
  for (;;) delay_ms(100);
}
