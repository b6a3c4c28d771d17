/* Register-level test firmware: each TWI step's status and each bus byte's time, polled as
 * closely as a master can (timer1 at clk/1 counts the cycles). TWI at 400 kHz: TWBR = 12, an SCL
 * period of 16 + 2 * 12 = 40 cycles (datasheet 24.5.2). It reads the HMC5883L's identification
 * (registers 0Ah..0Ch, "H43") with a repeated start, then addresses 0x33, where nobody answers,
 * once to write and once to read. SPI at clk/16 (SPR 01), mode 3: an SCK period of 16 cycles
 * (1 MHz, the MPU-6000's limit for registers other than its sensors'), reading its WHO_AM_I (0x75)
 * with chip select on pin 53 (PB0). The answer goes out on
 * USART0 at 115200 baud as "twi" and the statuses in hex, "h" and the ID bytes, "t" and the
 * cycles from the TWCR write of the register byte to TWINT, "spi" and WHO_AM_I, "t" and the
 * cycles from the SPDR write of the second byte to SPIF. */
#include <avr/io.h>

static void put(char c) {
  while (!(UCSR0A & _BV(UDRE0))) {
  }
  UDR0 = (uint8_t)c;
}

static void put_hex(uint8_t v) {
  static const char digits[] = "0123456789ABCDEF";
  put(' ');
  put(digits[v >> 4]);
  put(digits[v & 15]);
}

static void put_dec(uint16_t v) {
  char d[6];
  uint8_t n = 0;
  do {
    d[n++] = (char)('0' + v % 10);
    v /= 10;
  } while (v);
  put(' ');
  while (n) put(d[--n]);
}

static uint8_t statuses[12], status_count;
static uint16_t twi_byte_cycles;

/* One bus step: TWCR written, TWINT polled, the status kept. */
static void step(uint8_t twcr) {
  TWCR = twcr;
  while (!(TWCR & _BV(TWINT))) {
  }
  statuses[status_count++] = TWSR & 0xF8;
}

#define GO (_BV(TWINT) | _BV(TWEN))

static void stop(void) {
  TWCR = _BV(TWINT) | _BV(TWSTO) | _BV(TWEN);
  while (TWCR & _BV(TWSTO)) {
  }
}

int main(void) {
  UBRR0 = 16;
  UCSR0A = _BV(U2X0);
  UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
  UCSR0B = _BV(TXEN0);
  TCCR1B = _BV(CS10);
  TWSR = 0;
  TWBR = 12;
  TWCR = _BV(TWEN);

  uint8_t id[3];
  step(GO | _BV(TWSTA));
  TWDR = 0x1E << 1;
  step(GO);
  TWDR = 0x0A;
  const uint16_t t0 = TCNT1;
  TWCR = GO;
  while (!(TWCR & _BV(TWINT))) {
  }
  twi_byte_cycles = (uint16_t)(TCNT1 - t0);
  statuses[status_count++] = TWSR & 0xF8;
  step(GO | _BV(TWSTA));
  TWDR = 0x1E << 1 | 1;
  step(GO);
  step(GO | _BV(TWEA));
  id[0] = TWDR;
  step(GO | _BV(TWEA));
  id[1] = TWDR;
  step(GO);
  id[2] = TWDR;
  stop();
  step(GO | _BV(TWSTA));
  TWDR = 0x33 << 1;
  step(GO);
  stop();
  step(GO | _BV(TWSTA));
  TWDR = 0x33 << 1 | 1;
  step(GO);
  stop();

  PORTB |= _BV(PB0);
  DDRB |= _BV(PB0) | _BV(PB1) | _BV(PB2);
  SPCR = _BV(SPE) | _BV(MSTR) | _BV(CPOL) | _BV(CPHA) | _BV(SPR0);
  PORTB &= (uint8_t)~_BV(PB0);
  SPDR = 0x80 | 0x75;
  while (!(SPSR & _BV(SPIF))) {
  }
  const uint16_t t1 = TCNT1;
  SPDR = 0;
  while (!(SPSR & _BV(SPIF))) {
  }
  const uint16_t spi_byte_cycles = (uint16_t)(TCNT1 - t1);
  const uint8_t who = SPDR;
  PORTB |= _BV(PB0);

  put('t');
  put('w');
  put('i');
  for (uint8_t i = 0; i < status_count; ++i) put_hex(statuses[i]);
  put(' ');
  put('h');
  for (uint8_t i = 0; i < 3; ++i) put_hex(id[i]);
  put(' ');
  put('t');
  put_dec(twi_byte_cycles);
  put(' ');
  put('s');
  put('p');
  put('i');
  put_hex(who);
  put(' ');
  put('t');
  put_dec(spi_byte_cycles);
  put('\n');
  for (;;) {
  }
}
