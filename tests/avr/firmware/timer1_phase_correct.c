/* Register-level test firmware: timer1 in phase-correct 8-bit PWM (mode 1, WGM10) at clk/64, the
 * mode the Arduino core and SEAR's HAL leave timers 1..5 in, with its overflow interrupt on. */
#include <avr/interrupt.h>
#include <avr/io.h>

ISR(TIMER1_OVF_vect) { PINB = _BV(PB7); }

int main(void) {
  DDRB |= _BV(PB7);
  TCCR1A = _BV(WGM10);
  TCCR1B = _BV(CS11) | _BV(CS10);
  TIMSK1 = _BV(TOIE1);
  sei();
  for (;;) {
  }
}
