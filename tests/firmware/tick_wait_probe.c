/* Waits for each tick of a 1 kHz timer in `while (!flag) {}`, a thousand times, and prints how many
 * waits ended exactly at their tick, and when the last one did. */
#include <hal/hal.h>
#include <stdio.h>

#define WAITS 1000u

static volatile uint8_t ticked;
static void tick(void) { ticked = 1; }

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  irq_timer_start(1000, tick);
  /* The timer starts at 6.25 us, after two calls of 3.125 us; tick k falls due at 1006.25 us + k ms. */
  const uint32_t first_us = 1006;
  uint32_t exact = 0, last = 0;
  for (uint32_t k = 0; k < WAITS; ++k) {
    while (!ticked) {
    }
    ticked = 0;
    last = micros();
    /* The wait ends at the tick itself (1006.25 us + k ms), where micros() then acts. */
    if (last == first_us + 1000u * k) ++exact;
  }
  char line[80];
  snprintf(line, sizeof line, "%lu of %lu waits ended at their tick, the last at %lu us\n", (unsigned long)exact,
           (unsigned long)WAITS, (unsigned long)last);
  uart_print(0, line);
  for (;;) delay_ms(100);
}
