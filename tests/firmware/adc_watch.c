/* Reads ADC channel 0 every millisecond and prints the time (us) whenever the reading changes. */
#include <hal/hal.h>
#include <stdio.h>

int main(void) {
  hal_init();
  uart_begin(0, 1000000);
  uint16_t last = 0xFFFF;
  char line[40];
  for (;;) {
    const uint32_t t = micros();
    const uint16_t code = adc_read(0);
    if (code != last) {
      snprintf(line, sizeof line, "%lu %u\n", (unsigned long)t, code);
      uart_print(0, line);
      last = code;
    }
    delay_ms(1);
  }
}
