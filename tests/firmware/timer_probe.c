/* Lockstep timing probe, run with hal_call_cycles="0" so that only delays and the timer move the
 * clock: pin 12 toggles every 10 ms from a delay loop, pin 13 every 10 ticks of a 1 kHz timer
 * interrupt, and the console reports the ticks counted after each whole second. */
#include <hal/hal.h>
#include <stdio.h>

static volatile uint32_t ticks;

static void tick(void) {
  ticks++;
  if (ticks % 10 == 0) digital_toggle(13);
}

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  pin_mode(12, OUTPUT);
  pin_mode(13, OUTPUT);
  irq_timer_start(1000, tick);
  char line[32];
  for (uint16_t ms = 1;; ++ms) {
    delay_ms(10);
    digital_toggle(12);
    if (ms % 100 == 0) {
      snprintf(line, sizeof line, "ticks %lu\n", (unsigned long)ticks);
      uart_print(0, line);
    }
  }
}
