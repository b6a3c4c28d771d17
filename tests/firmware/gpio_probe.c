/* Pins and interrupts behave as on the ATmega2560: an input's latch is its pull-up, full-scale
 * PWM drives a motor whatever the pin's latch held, and an interrupt handler that disables
 * interrupts gets them back on return (RETI). Motor "left" is wired to PWM 3, direction 12. */
#include <hal/hal.h>
#include <stdio.h>

static volatile uint16_t ticks;

static void tick(void) {
  ticks++;
  irq_disable();
}

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  pin_mode(30, INPUT);
  digital_write(30, HIGH); /* on an input: the pull-up */
  const uint8_t a = digital_read(30);
  pin_mode(31, INPUT_PULLUP);
  pin_mode(31, OUTPUT); /* the latch still holds HIGH */
  const uint8_t b = digital_read(31);
  digital_write(32, HIGH);
  pin_mode(32, INPUT); /* clears the latch */
  pin_mode(32, OUTPUT);
  const uint8_t c = digital_read(32);

  digital_write(3, HIGH); /* latch preset while still an input */
  pin_mode(12, OUTPUT);
  digital_write(12, HIGH);
  pwm_write(3, 255);

  irq_timer_start(1000, tick);
  delay_ms(100);
  irq_timer_stop();

  char line[48];
  snprintf(line, sizeof line, "a=%u b=%u c=%u ticks=%u\n", a, b, c, ticks);
  uart_print(0, line);
  for (;;) delay_ms(100);
}
