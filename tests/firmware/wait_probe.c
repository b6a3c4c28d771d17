/* Waits for interrupts in loops that make no HAL call: `while (!flag) {}` for a 100 ms timer's
 * flag, five times, printing when each wait ended; then for a bump switch's falling edge. */
#include <hal/hal.h>
#include <stdio.h>

static volatile uint8_t ticked;
static volatile uint8_t bumped;

static void tick(void) { ticked = 1; }
static void bump(void) { bumped = 1; }

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  irq_timer_start(100000, tick);
  uint32_t ended[5];
  for (uint8_t i = 0; i < 5; ++i) {
    while (!ticked) {
    }
    ended[i] = micros();
    ticked = 0;
  }
  irq_timer_stop();
  char line[80];
  snprintf(line, sizeof line, "waits ended at %lu %lu %lu %lu %lu us\n", (unsigned long)ended[0],
           (unsigned long)ended[1], (unsigned long)ended[2], (unsigned long)ended[3], (unsigned long)ended[4]);
  uart_print(0, line);

  pin_mode(2, INPUT_PULLUP);
  irq_attach_pin(2, IRQ_FALLING, bump);
  while (!bumped) {
  }
  snprintf(line, sizeof line, "bumped at %lu us\n", (unsigned long)micros());
  uart_print(0, line);
  for (;;) delay_ms(100);
}
