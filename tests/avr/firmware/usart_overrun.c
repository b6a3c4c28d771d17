/* Register-level test firmware: USART0 at 9600 baud 8N1 receives without reading for 20 ms (timer1
 * at clk/1024 counts 312 ticks, 19.97 ms), then answers on its TX: '!' if DOR0 is set, every byte
 * the receiver still holds, and '.' if DOR0 is clear once they are read. */
#include <avr/io.h>

static void send(uint8_t byte) {
  while (!(UCSR0A & _BV(UDRE0))) {
  }
  UDR0 = byte;
}

int main(void) {
  UBRR0 = 103;
  UCSR0A = 0;
  UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
  UCSR0B = _BV(RXEN0) | _BV(TXEN0);
  TCCR1B = _BV(CS12) | _BV(CS10);
  while (TCNT1 < 312) {
  }
  if (UCSR0A & _BV(DOR0)) send('!');
  while (UCSR0A & _BV(RXC0)) send(UDR0);
  if (!(UCSR0A & _BV(DOR0))) send('.');
  for (;;) {
  }
}
