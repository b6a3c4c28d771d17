/* Register-level test firmware: the left motor runs from timer3's OC3C (pin 3, PE5) in 8-bit fast
 * PWM, a quadrature encoder on pins 10 and 11 (PB4, PB5) raises PCINT0 on each edge (PCMSK0 bits
 * 4 and 5, datasheet 15.2.7), and the naked ISR answers each edge by toggling pin 22 (PA0) through
 * PINA: one SBI (2 cycles) after the vector's JMP (3 cycles), so the answer's delay shows what the
 * engine adds to the chip's arithmetic. */
#include <avr/interrupt.h>
#include <avr/io.h>

ISR(PCINT0_vect, ISR_NAKED) {
  __asm__ volatile("sbi %0, 0\n\treti" ::"I"(_SFR_IO_ADDR(PINA)));
}

int main(void) {
  DDRA |= _BV(PA0);
  DDRE |= _BV(PE5);
  DDRB |= _BV(PB6); /* the motor's direction pin (12), LOW: forward */
  OCR3C = 200;
  TCCR3A = _BV(COM3C1) | _BV(WGM30);
  TCCR3B = _BV(WGM32) | _BV(CS31) | _BV(CS30);
  PCMSK0 = _BV(PCINT4) | _BV(PCINT5);
  PCICR = _BV(PCIE0);
  sei();
  for (;;) {
  }
}
