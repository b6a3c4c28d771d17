/* HC-SR04 ultrasonic ranger (../lib/hcsr04): a 10 us pulse on TRIG starts a ping, and ECHO stays
 * HIGH for the sound's round trip, timed by a pin-change interrupt; one ping per 65 ms cycle,
 * printed in cm. Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include <hal/hal.h>
#include <stdio.h>

#include "../lib/hcsr04.h"

#define CONSOLE 0
#define TRIG_PIN 24 /* output */
#define ECHO_PIN 10 /* input with a pin-change interrupt (PCINT4) */

/* One ping: the echo's high time in microseconds, or 0 when none came back in time. */
static uint32_t ping(void) {
  hcsr04_trigger();
  const uint32_t start = millis();
  uint32_t width = 0;
  while (!hcsr04_done(&width) && millis() - start < HCSR04_CYCLE_MS) delay_ms(1);
  return width;
}

int main(void) {
  hal_init();
  uart_begin(CONSOLE, 115200);
  hcsr04_begin(TRIG_PIN, ECHO_PIN);
  uart_print(CONSOLE, "hcsr04_ping: ready\r\n");
  delay_ms(HCSR04_CYCLE_MS);

  char line[64];
  uint32_t n = 0;
  for (;;) {
    const uint32_t cycle_start = millis();
    const uint32_t width = ping();
    ++n;
    if (width == 0 || width >= HCSR04_NO_ECHO_US) {
      snprintf(line, sizeof line, "ping %lu: no echo\r\n", (unsigned long)n);
    } else {
      const uint32_t tenths_cm = (width * 10u + HCSR04_US_PER_CM / 2) / HCSR04_US_PER_CM;
      snprintf(line, sizeof line, "ping %lu: %lu us, %lu.%lu cm\r\n", (unsigned long)n, (unsigned long)width,
               (unsigned long)(tenths_cm / 10u), (unsigned long)(tenths_cm % 10u));
    }
    uart_print(CONSOLE, line);
    /* the next ping only once this cycle's 60 ms are over, so that no late echo of this one
     * is taken for the next one's */
    while (millis() - cycle_start < HCSR04_CYCLE_MS) delay_ms(1);
  }
}
