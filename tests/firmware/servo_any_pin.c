/* servo_write_us on pin 30, which has no timer (the AVR target's timer5 interrupt makes its
 * pulses): 1500 us from the start, 2000 us from 1 s, none from 2 s. */
#include <hal/hal.h>

int main(void) {
  hal_init();
  servo_write_us(30, 1500);
  delay_ms(1000);
  servo_write_us(30, 2000);
  delay_ms(1000);
  servo_write_us(30, 0);
  for (;;) delay_ms(100);
}
