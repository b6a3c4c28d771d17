/* Pin 30, wired to a servo, made an OUTPUT and held HIGH: a level, not servo pulses. */
#include <hal/hal.h>

int main(void) {
  hal_init();
  pin_mode(30, OUTPUT);
  digital_write(30, HIGH);
  for (;;) delay_ms(100);
}
