/* Register-level test firmware: USART0 at 9600 baud (UBRR0 = 103: 16 MHz / (16 * 104) = 9615 baud,
 * datasheet table 22-12), 8N1; the RX complete interrupt sends each byte back plus one. */
#include <avr/interrupt.h>
#include <avr/io.h>

ISR(USART0_RX_vect) {
  const uint8_t byte = UDR0;
  UDR0 = (uint8_t)(byte + 1);
}

int main(void) {
  UBRR0 = 103;
  UCSR0A = 0;
  UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
  UCSR0B = _BV(RXEN0) | _BV(TXEN0) | _BV(RXCIE0);
  sei();
  for (;;) {
  }
}
