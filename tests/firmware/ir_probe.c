/* Reads ADC channels 0..3 (Sharp GP2D12 rangers) every 100 ms and prints the 10-bit codes. */
#include <hal/hal.h>
#include <stdio.h>

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  char line[48];
  for (;;) {
    delay_ms(100);
    snprintf(line, sizeof line, "adc %u %u %u %u\n", adc_read(0), adc_read(1), adc_read(2), adc_read(3));
    uart_print(0, line);
  }
}
