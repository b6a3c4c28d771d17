/* Reads pin 22 (a Sharp GP2D15 proximity switch) every millisecond and prints "t_us level" each
 * time the level it reads changes, the first reading included; t_us is micros() just before the
 * read. */
#include <hal/hal.h>
#include <stdio.h>

#define PIN 22

int main(void) {
  hal_init();
  uart_begin(0, 1000000);
  pin_mode(PIN, INPUT);
  uint8_t last = 0xFF;
  char line[32];
  for (;;) {
    const uint32_t t = micros();
    const uint8_t level = digital_read(PIN);
    if (level != last) {
      snprintf(line, sizeof line, "%lu %u\n", (unsigned long)t, level);
      uart_print(0, line);
      last = level;
    }
    delay_ms(1);
  }
}
