/* Firmware timing probe: pin 13 toggles around delay_us() calls of many lengths (shorter than one
 * HAL call's cost, a few calls long, across quantum ends, several quanta long), around delay_ms(),
 * around one adc_read() and after a busy-wait on micros(), so that the pin waveform's edge times
 * (VCD, 1 ns) show what each call cost. The micros() value read after each toggle is printed at
 * the end, after the timed part, with the adc reading and a marker line. Nothing here depends on
 * the clock rate: the test derives every time from the MCU's hal_call_cycles and clock_hz. */
#include <hal/hal.h>
#include <stdio.h>

#define PIN 13

/* Keep in step with kDelaysUs in tests/firmware_timing_test.cpp. */
static const uint32_t delays_us[] = {0, 1, 2, 3, 4, 7, 13, 100, 997, 1000, 1001, 2500, 12345};
#define DELAYS (sizeof delays_us / sizeof delays_us[0])

int main(void) {
  uint32_t stamps[DELAYS];
  hal_init();
  pin_mode(PIN, OUTPUT);
  for (unsigned i = 0; i < DELAYS; ++i) {
    digital_toggle(PIN);
    stamps[i] = micros();
    delay_us(delays_us[i]);
  }
  digital_toggle(PIN);
  delay_ms(1);
  digital_toggle(PIN);
  delay_ms(3);
  digital_toggle(PIN);
  const uint16_t code = adc_read(0);
  digital_toggle(PIN);
  while (micros() < 50000u) {
  }
  digital_toggle(PIN);

  uart_begin(0, 1000000);
  char line[32];
  for (unsigned i = 0; i < DELAYS; ++i) {
    snprintf(line, sizeof line, "stamp %u %lu\n", i, (unsigned long)stamps[i]);
    uart_print(0, line);
  }
  snprintf(line, sizeof line, "adc %u\n", code);
  uart_print(0, line);
  uart_print(0, "done\n");
  for (;;) delay_ms(1000);
}
