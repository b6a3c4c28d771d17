/* Prints a line, starts a 1 kHz timer whose handler toggles pin 13 (and prints every 100th tick),
 * then ends in `for (;;);`, the idiom for "stop here": the MCU halts there, its interrupts still
 * running. With HALT_IRQ_OFF (set per build by tests/CMakeLists.txt) it turns interrupts off
 * first, and nothing more runs. */
#include <hal/hal.h>
#include <stdio.h>

static volatile uint32_t ticks;

static void tick(void) {
  digital_toggle(13);
  if (++ticks % 100 == 0) {
    char line[24];
    snprintf(line, sizeof line, "tick %lu\n", (unsigned long)ticks);
    uart_print(0, line);
  }
}

int main(void) {
  hal_init();
  uart_begin(0, 9600);
  pin_mode(13, OUTPUT);
  irq_timer_start(1000, tick);
  /* 62 bytes at 9600 baud: 64.6 ms on the wire, nearly all of it after the loop began. */
  uart_print(0, "halting: every byte of this line leaves after the loop began.\n");
#ifdef HALT_IRQ_OFF
  irq_disable();
#endif
  for (;;) {
  }
}
