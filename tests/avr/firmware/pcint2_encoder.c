/* Register-level test firmware: pcint_encoder.c on the third pin-change bank, which simavr 1.6's
 * ATmega2560 lacks (the engine adds it): the encoder on A8 and A9 (PK0, PK1) raises PCINT2 on
 * each edge (PCMSK2 bits 0 and 1, datasheet 15.2.5), and the naked ISR answers each edge by
 * toggling pin 22 (PA0) through PINA. */
#include <avr/interrupt.h>
#include <avr/io.h>

ISR(PCINT2_vect, ISR_NAKED) {
  __asm__ volatile("sbi %0, 0\n\treti" ::"I"(_SFR_IO_ADDR(PINA)));
}

int main(void) {
  DDRA |= _BV(PA0);
  DDRE |= _BV(PE5);
  DDRB |= _BV(PB6); /* the motor's direction pin (12), LOW: forward */
  OCR3C = 200;
  TCCR3A = _BV(COM3C1) | _BV(WGM30);
  TCCR3B = _BV(WGM32) | _BV(CS31) | _BV(CS30);
  PCMSK2 = _BV(PCINT16) | _BV(PCINT17);
  PCICR = _BV(PCIE2);
  sei();
  for (;;) {
  }
}
