/* Register-level test firmware: the ADC free-running on ADC0 against AVcc at clk/128, its
 * conversion-complete interrupt toggling pin 12 (PB6) once per conversion (13 ADC clocks of 128
 * cycles: 1664 cycles, 104 us at 16 MHz, datasheet 26.4); after 100 conversions it reports the
 * last result on USART0 at 115200 baud (U2X, UBRR0 = 16) as "adc NNNN\n". */
#include <avr/interrupt.h>
#include <avr/io.h>

static volatile uint16_t result;
static volatile uint8_t conversions;

ISR(ADC_vect) {
  result = ADC;
  PINB = _BV(PB6);
  if (conversions < 255) conversions++;
}

static void put(char c) {
  while (!(UCSR0A & _BV(UDRE0))) {
  }
  UDR0 = (uint8_t)c;
}

int main(void) {
  UBRR0 = 16;
  UCSR0A = _BV(U2X0);
  UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
  UCSR0B = _BV(TXEN0);
  DDRB |= _BV(PB6);
  ADMUX = _BV(REFS0); /* AVcc, channel 0 */
  ADCSRB = 0;         /* free running */
  ADCSRA = _BV(ADEN) | _BV(ADSC) | _BV(ADATE) | _BV(ADIE) | _BV(ADPS2) | _BV(ADPS1) | _BV(ADPS0);
  sei();
  while (conversions < 100) {
  }
  cli();
  const uint16_t v = result;
  sei();
  put('a');
  put('d');
  put('c');
  put(' ');
  for (uint16_t div = 1000; div; div /= 10) put((char)('0' + v / div % 10));
  put('\n');
  for (;;) {
  }
}
