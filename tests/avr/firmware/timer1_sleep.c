/* Register-level test firmware: timer1 in CTC mode at clk/8 with OCR1A = 1999 wakes the chip every
 * 16000 cycles (1 ms at 16 MHz); its ISR toggles pin 13 and the chip sleeps (idle mode) again. */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>

ISR(TIMER1_COMPA_vect) { PINB = _BV(PB7); }

int main(void) {
  DDRB |= _BV(PB7);
  OCR1A = 1999;
  TCCR1A = 0;
  TCCR1B = _BV(WGM12) | _BV(CS11);
  TIMSK1 = _BV(OCIE1A);
  set_sleep_mode(SLEEP_MODE_IDLE);
  sei();
  for (;;) sleep_mode();
}
