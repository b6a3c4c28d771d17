/* ADC probe: once the rover has settled (400 ms), reads channels 0..3 (Sharp GP2D12 rangers) under
 * every reference and resolution the HAL offers, one console line each:
 *   "ref R bits B: c0 c1 c2 c3"  with R 0 AVCC, 1 EXTERNAL (the mcu's aref), 2 the internal 1.1 V. */
#include <hal/hal.h>
#include <stdio.h>

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  delay_ms(400);
  static const uint8_t refs[] = {ADC_REF_AVCC, ADC_REF_EXTERNAL, ADC_REF_1V1};
  static const uint8_t bits[] = {10, 8};
  char line[64];
  for (unsigned b = 0; b < sizeof bits; ++b) {
    adc_resolution(bits[b]);
    for (unsigned r = 0; r < sizeof refs; ++r) {
      adc_reference(refs[r]);
      snprintf(line, sizeof line, "ref %u bits %u: %u %u %u %u\n", refs[r], bits[b], adc_read(0), adc_read(1), adc_read(2),
               adc_read(3));
      uart_print(0, line);
    }
  }
  uart_print(0, "done\n");
  for (;;) delay_ms(1000);
}
