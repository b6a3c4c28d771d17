/* The Arduino Mega's pin numbering: which port, bit and timer channel each of pins 0..69 uses
 * (the board's schematic, ATmega2560 datasheet "Alternate Port Functions"). */
#include "pin_map.h"
#include "timers.h"

#include <avr/io.h>
#include <avr/pgmspace.h>
#include <util/atomic.h>

/* Ports in the order of port_pin_register: A B C D E F G H J K L (there is no port I). */
enum { PA_, PB_, PC_, PD_, PE_, PF_, PG_, PH_, PJ_, PK_, PL_ };

/* Port in bits 7..3, bit number in bits 2..0: one flash byte per pin instead of a RAM table. */
#define P(port, bit) (uint8_t)(((port) << 3) | (bit))

static const uint8_t pin_port_bit[70] PROGMEM = {
    P(PE_, 0), P(PE_, 1), P(PE_, 4), P(PE_, 5), P(PG_, 5), /* 0..4 */
    P(PE_, 3), P(PH_, 3), P(PH_, 4), P(PH_, 5), P(PH_, 6), /* 5..9 */
    P(PB_, 4), P(PB_, 5), P(PB_, 6), P(PB_, 7), P(PJ_, 1), /* 10..14 */
    P(PJ_, 0), P(PH_, 1), P(PH_, 0), P(PD_, 3), P(PD_, 2), /* 15..19 */
    P(PD_, 1), P(PD_, 0), P(PA_, 0), P(PA_, 1), P(PA_, 2), /* 20..24 */
    P(PA_, 3), P(PA_, 4), P(PA_, 5), P(PA_, 6), P(PA_, 7), /* 25..29 */
    P(PC_, 7), P(PC_, 6), P(PC_, 5), P(PC_, 4), P(PC_, 3), /* 30..34 */
    P(PC_, 2), P(PC_, 1), P(PC_, 0), P(PD_, 7), P(PG_, 2), /* 35..39 */
    P(PG_, 1), P(PG_, 0), P(PL_, 7), P(PL_, 6), P(PL_, 5), /* 40..44 */
    P(PL_, 4), P(PL_, 3), P(PL_, 2), P(PL_, 1), P(PL_, 0), /* 45..49 */
    P(PB_, 3), P(PB_, 2), P(PB_, 1), P(PB_, 0), P(PF_, 0), /* 50..54 (A0) */
    P(PF_, 1), P(PF_, 2), P(PF_, 3), P(PF_, 4), P(PF_, 5), /* 55..59 */
    P(PF_, 6), P(PF_, 7), P(PK_, 0), P(PK_, 1), P(PK_, 2), /* 60..64 (A8 = 62) */
    P(PK_, 3), P(PK_, 4), P(PK_, 5), P(PK_, 6), P(PK_, 7), /* 65..69 */
};

/* Ports H, J, K and L lie outside the I/O space, so addresses rather than I/O numbers. */
static const uint16_t port_pin_register[11] PROGMEM = {
    _SFR_MEM_ADDR(PINA), _SFR_MEM_ADDR(PINB), _SFR_MEM_ADDR(PINC), _SFR_MEM_ADDR(PIND),
    _SFR_MEM_ADDR(PINE), _SFR_MEM_ADDR(PINF), _SFR_MEM_ADDR(PING), _SFR_MEM_ADDR(PINH),
    _SFR_MEM_ADDR(PINJ), _SFR_MEM_ADDR(PINK), _SFR_MEM_ADDR(PINL),
};

/* 1 << n by lookup: the AVR shifts one bit per instruction. */
static const uint8_t bit_mask[8] PROGMEM = {0x01, 0x02, 0x04, 0x08, 0x10, 0x20, 0x40, 0x80};

pin_io hal_avr_pin_io(uint8_t pin)
{
    pin_io io = {0, 0};
    if (pin < sizeof pin_port_bit) {
        uint8_t port_bit = pgm_read_byte(&pin_port_bit[pin]);
        io.pin = (volatile uint8_t *)pgm_read_word(&port_pin_register[port_bit >> 3]);
        io.mask = pgm_read_byte(&bit_mask[port_bit & 7u]);
    }
    return io;
}

#define T(timer, channel) (uint8_t)(((timer) << 4) | (channel))

uint8_t hal_avr_pin_timer(uint8_t pin)
{
    /* Pin 13 (PB7) is also OC1C; like the Arduino core it uses OC0A so that timer1 keeps two
     * channels for servos on 11 and 12 only. */
    switch (pin) {
    case 2: return T(3, 1);  /* PE4 OC3B */
    case 3: return T(3, 2);  /* PE5 OC3C */
    case 4: return T(0, 1);  /* PG5 OC0B */
    case 5: return T(3, 0);  /* PE3 OC3A */
    case 6: return T(4, 0);  /* PH3 OC4A */
    case 7: return T(4, 1);  /* PH4 OC4B */
    case 8: return T(4, 2);  /* PH5 OC4C */
    case 9: return T(2, 1);  /* PH6 OC2B */
    case 10: return T(2, 0); /* PB4 OC2A */
    case 11: return T(1, 0); /* PB5 OC1A */
    case 12: return T(1, 1); /* PB6 OC1B */
    case 13: return T(0, 0); /* PB7 OC0A */
    case 44: return T(5, 2); /* PL5 OC5C */
    case 45: return T(5, 1); /* PL4 OC5B */
    case 46: return T(5, 0); /* PL3 OC5A */
    default: return PIN_NO_TIMER;
    }
}

void hal_avr_pin_timer_off(uint8_t pin)
{
    uint8_t code = hal_avr_pin_timer(pin);
    if (code == PIN_NO_TIMER)
        return;
    uint8_t bits = TIMER_COM_BITS(PIN_TIMER_CHANNEL(code));
    volatile uint8_t *tccra = hal_avr_timer_tccra(PIN_TIMER_NUMBER(code));
    /* Handlers may call pwm_write too, and TCCRnA holds the other channels' bits. */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        *tccra = (uint8_t)(*tccra & ~bits);
    }
}
