/* Timer5 asked for twice on the AVR target: the periodic interrupt and servo pulses on pin 30,
 * which has no timer of its own (SERVO_FIRST: the other way round). The second call stops the
 * chip, its reason written on the console (UART 0) first. */
#include <hal/hal.h>

static void tick(void) {}

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  uart_print(0, "start\n");
#ifdef SERVO_FIRST
  servo_write_us(30, 1500);
  delay_ms(10);
  irq_timer_start(1000, tick);
#else
  irq_timer_start(1000, tick);
  delay_ms(10);
  servo_write_us(30, 1500);
#endif
  uart_print(0, "not reached\n");
  for (;;) delay_ms(100);
}
