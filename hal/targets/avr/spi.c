/* The SPI master on MOSI 51 (PB2), MISO 50 (PB3), SCK 52 (PB1), with SS 53 (PB0) kept an output
 * so that a low level on it can never turn the peripheral into a slave. */
#include <hal/spi.h>

#include <avr/io.h>

void spi_begin(uint8_t mode, uint32_t clock_hz)
{
    /* SS first: driven high (no device of ours selected by it) before it becomes an output,
     * unless the firmware already uses it as one. */
    if (!(DDRB & _BV(DDB0))) {
        PORTB |= _BV(PB0);
        DDRB |= _BV(DDB0);
    }

    /* The slowest divider 2^n (n = 1..7) whose clock is still <= clock_hz, or /128. */
    uint8_t shift = 1;
    while (shift < 7 && (F_CPU >> shift) > clock_hz)
        shift++;
    /* Datasheet, "Relationship between SCK and the oscillator frequency": SPR1:0 = 0..3 picks
     * /4, /16, /64, /128 and SPI2X halves the first three, so an odd n below 7 is SPI2X. */
    uint8_t double_speed = (shift & 1u) && shift < 7;
    uint8_t spr = (uint8_t)((shift - 1u) >> 1);

    uint8_t spcr = (uint8_t)(_BV(SPE) | _BV(MSTR) | spr);
    if (mode & 2u)
        spcr |= _BV(CPOL);
    if (mode & 1u)
        spcr |= _BV(CPHA);
    SPCR = spcr;
    SPSR = double_speed ? _BV(SPI2X) : 0;

    /* Outputs only after SPE|MSTR, so SCK starts at the idle level CPOL gives it. */
    DDRB |= _BV(DDB2) | _BV(DDB1);
    DDRB &= (uint8_t)~_BV(DDB3);
}

uint8_t spi_transfer(uint8_t out)
{
    /* Without spi_begin (or after a low SS dropped master mode) SPIF would never come. */
    if ((SPCR & (_BV(SPE) | _BV(MSTR))) != (_BV(SPE) | _BV(MSTR)))
        return 0xFF;
    SPDR = out;
    while (!(SPSR & _BV(SPIF))) {
    }
    return SPDR;
}
