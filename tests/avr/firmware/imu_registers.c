/* Register-level test firmware: the TWI master reads the MPU-6050's WHO_AM_I (0x75) at address
 * 0x68 and the SPI master the MPU-6000's, chip select on pin 53 (PB0), with no library; both
 * bytes go out on USART0 at 115200 baud as "twi XX spi XX\n" (hex). TWI at 100 kHz:
 * TWBR = (16 MHz / 100 kHz - 16) / 2 = 72 (datasheet 24.5.2); SPI at clk/16, mode 3. */
#include <avr/io.h>

static void put(char c) {
  while (!(UCSR0A & _BV(UDRE0))) {
  }
  UDR0 = (uint8_t)c;
}

static void put_hex(uint8_t v) {
  static const char digits[] = "0123456789ABCDEF";
  put(digits[v >> 4]);
  put(digits[v & 15]);
}

static void twi_wait(void) {
  while (!(TWCR & _BV(TWINT))) {
  }
}

static uint8_t twi_read_register(uint8_t address, uint8_t reg) {
  TWCR = _BV(TWINT) | _BV(TWSTA) | _BV(TWEN);
  twi_wait();
  TWDR = (uint8_t)(address << 1);
  TWCR = _BV(TWINT) | _BV(TWEN);
  twi_wait();
  TWDR = reg;
  TWCR = _BV(TWINT) | _BV(TWEN);
  twi_wait();
  TWCR = _BV(TWINT) | _BV(TWSTA) | _BV(TWEN); /* repeated start */
  twi_wait();
  TWDR = (uint8_t)(address << 1 | 1);
  TWCR = _BV(TWINT) | _BV(TWEN);
  twi_wait();
  TWCR = _BV(TWINT) | _BV(TWEN); /* one byte, NACKed */
  twi_wait();
  const uint8_t value = TWDR;
  TWCR = _BV(TWINT) | _BV(TWSTO) | _BV(TWEN);
  return value;
}

static uint8_t spi_byte(uint8_t out) {
  SPDR = out;
  while (!(SPSR & _BV(SPIF))) {
  }
  return SPDR;
}

int main(void) {
  UBRR0 = 16;
  UCSR0A = _BV(U2X0);
  UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
  UCSR0B = _BV(TXEN0);
  TWSR = 0;
  TWBR = 72;
  const uint8_t twi = twi_read_register(0x68, 0x75);

  PORTB |= _BV(PB0);                                /* chip select high before it drives */
  DDRB |= _BV(PB0) | _BV(PB1) | _BV(PB2);           /* SS, SCK, MOSI */
  SPCR = _BV(SPE) | _BV(MSTR) | _BV(CPOL) | _BV(CPHA) | _BV(SPR0);
  PORTB &= (uint8_t)~_BV(PB0);
  spi_byte(0x80 | 0x75);
  const uint8_t spi = spi_byte(0);
  PORTB |= _BV(PB0);

  put('t');
  put('w');
  put('i');
  put(' ');
  put_hex(twi);
  put(' ');
  put('s');
  put('p');
  put('i');
  put(' ');
  put_hex(spi);
  put('\n');
  for (;;) {
  }
}
