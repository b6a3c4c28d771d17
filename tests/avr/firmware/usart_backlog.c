/* Register-level test firmware: USART0 at 9600 baud 8N1 (UBRR0 = 103) with its receive interrupt,
 * held off for 5 ms (timer1 at clk/8 counts 10000 ticks) while three bytes arrive back to back,
 * the receiver holding them (two in its buffer, one in its shift register). Then the RX ISR runs
 * once per byte, keeping timer1 at each entry; the answer on TX is 'g' and the two gaps between
 * the entries in timer ticks (8 cycles each). */
#include <avr/interrupt.h>
#include <avr/io.h>

static volatile uint16_t entered[3];
static volatile uint8_t count;

ISR(USART0_RX_vect) {
  const uint16_t t = TCNT1;
  (void)UDR0;
  if (count < 3) entered[count++] = t;
}

static void send(uint8_t byte) {
  while (!(UCSR0A & _BV(UDRE0))) {
  }
  UDR0 = byte;
}

static void send_dec(uint16_t v) {
  char d[6];
  uint8_t n = 0;
  do {
    d[n++] = (char)('0' + v % 10);
    v /= 10;
  } while (v);
  send(' ');
  while (n) send((uint8_t)d[--n]);
}

int main(void) {
  UBRR0 = 103;
  UCSR0A = 0;
  UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
  UCSR0B = _BV(RXEN0) | _BV(TXEN0) | _BV(RXCIE0);
  TCCR1B = _BV(CS11);
  while (TCNT1 < 10000) {
  }
  sei();
  while (count < 3) {
  }
  send('g');
  send_dec((uint16_t)(entered[1] - entered[0]));
  send_dec((uint16_t)(entered[2] - entered[1]));
  send('\n');
  for (;;) {
  }
}
