/* Register-level test firmware: timer1 in CTC mode (WGM12) at clk/8 with OCR1A = 1999 raises
 * TIMER1_COMPA every (1999 + 1) * 8 = 16000 cycles, 1 ms at 16 MHz (datasheet 17.9.2); its ISR
 * toggles pin 13 (PB7) by writing PINB. */
#include <avr/interrupt.h>
#include <avr/io.h>

ISR(TIMER1_COMPA_vect) { PINB = _BV(PB7); }

int main(void) {
  DDRB |= _BV(PB7);
  OCR1A = 1999;
  TCCR1A = 0;
  TCCR1B = _BV(WGM12) | _BV(CS11);
  TIMSK1 = _BV(OCIE1A);
  sei();
  for (;;) {
  }
}
