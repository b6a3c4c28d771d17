/* Register-level test firmware for the wiring report: converts ADC channel 0 and reads PINB (pin
 * 10 is PB4) over and over, and touches nothing else. */
#include <avr/io.h>

volatile uint16_t sink;

int main(void) {
  ADMUX = _BV(REFS0); /* AVcc, channel 0 */
  ADCSRA = _BV(ADEN) | _BV(ADPS2) | _BV(ADPS1) | _BV(ADPS0);
  for (;;) {
    ADCSRA |= _BV(ADSC);
    while (ADCSRA & _BV(ADSC)) {
    }
    sink = (uint16_t)(ADC + (PINB & _BV(PB4)));
  }
}
