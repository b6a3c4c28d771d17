/* Edge interrupts on pins: INT0..INT5 (pins 21, 20, 19, 18, 2, 3), edge chosen in hardware, and
 * pin-change interrupts (10..15, 50..53, A8..A15), edge told from the previous level. */
#include <hal/irq.h>

#include <avr/interrupt.h>
#include <avr/io.h>
#include <stddef.h>
#include <util/atomic.h>

#define NO_LINE 0xFF

/* ---- External interrupts INT0..INT5 ---- */

static volatile irq_handler int_handlers[6];

static uint8_t int_line(uint8_t pin)
{
    switch (pin) {
    case 21: return 0; /* PD0 */
    case 20: return 1; /* PD1 */
    case 19: return 2; /* PD2 */
    case 18: return 3; /* PD3 */
    case 2: return 4;  /* PE4 */
    case 3: return 5;  /* PE5 */
    default: return NO_LINE;
    }
}

/* ISCn1:ISCn0 (datasheet table "Interrupt Sense Control"): 00 low level, 01 any edge, 10
 * falling, 11 rising. */
static uint8_t sense_bits(uint8_t edge)
{
    switch (edge) {
    case IRQ_LOW: return 0;
    case IRQ_RISING: return 3;
    case IRQ_FALLING: return 2;
    default: return 1;
    }
}

static void attach_int(uint8_t line, uint8_t edge, irq_handler handler)
{
    uint8_t bit = (uint8_t)_BV(line);
    /* EICRA holds INT0..3, EICRB INT4..7, two bits each. */
    volatile uint8_t *eicr = line < 4 ? &EICRA : &EICRB;
    uint8_t shift = (uint8_t)(2u * (line & 3u));
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        /* The datasheet's order: masked while the sense bits change, which can raise the flag,
         * then the flag cleared (by writing one) before unmasking. */
        EIMSK &= (uint8_t)~bit;
        int_handlers[line] = handler;
        *eicr = (uint8_t)((*eicr & ~(3u << shift)) | (uint8_t)(sense_bits(edge) << shift));
        EIFR = bit;
        EIMSK |= bit;
    }
}

static void run_int(uint8_t line)
{
    irq_handler handler = int_handlers[line];
    if (handler)
        handler();
}

ISR(INT0_vect) { run_int(0); }
ISR(INT1_vect) { run_int(1); }
ISR(INT2_vect) { run_int(2); }
ISR(INT3_vect) { run_int(3); }
ISR(INT4_vect) { run_int(4); }
ISR(INT5_vect) { run_int(5); }

/* ---- Pin-change interrupts, banks PCINT7..0, PCINT15..8, PCINT23..16 ---- */

typedef struct {
    irq_handler handlers[8];
    uint8_t rising, falling; /* which PCMSKn bits want which edge */
    uint8_t last;            /* levels seen by the previous interrupt, in PCMSKn bit order */
} change_bank;

static change_bank banks[3];

/* Bank in bits 7..4, PCMSKn bit in 2..0. */
static uint8_t change_line(uint8_t pin)
{
    if (pin >= 10 && pin <= 13)
        return (uint8_t)(pin - 6); /* PB4..PB7 = PCINT4..7 */
    if (pin >= 50 && pin <= 53)
        return (uint8_t)(53 - pin); /* PB3..PB0 = PCINT3..0 */
    if (pin == 14)
        return 0x12; /* PJ1 = PCINT10 */
    if (pin == 15)
        return 0x11; /* PJ0 = PCINT9 */
    if (pin >= 62 && pin <= 69)
        return (uint8_t)(0x20 | (pin - 62)); /* A8..A15 = PK0..PK7 = PCINT16..23 */
    return NO_LINE;
}

/* The bank's pin levels in PCMSKn bit order. Bank 1 is PCINT8 = PE0 followed by
 * PCINT9..15 = PJ0..PJ6. */
static uint8_t bank_levels(uint8_t bank)
{
    switch (bank) {
    case 0: return PINB;
    case 1: return (uint8_t)((PINJ << 1) | (PINE & 1u));
    default: return PINK;
    }
}

/* PCMSK0..2 sit at consecutive addresses (0x6B..0x6D). */
static volatile uint8_t *bank_mask(uint8_t bank)
{
    return &PCMSK0 + bank;
}

/* A pulse shorter than the interrupt latency shows no change here and is lost; that is the
 * price of pin-change interrupts, which is why INT pins are the better choice for such. */
static void run_change(uint8_t bank)
{
    change_bank *b = &banks[bank];
    uint8_t now = bank_levels(bank);
    uint8_t changed = (uint8_t)((now ^ b->last) & *bank_mask(bank));
    b->last = now;
    uint8_t due = (uint8_t)((changed & now & b->rising) | (changed & (uint8_t)~now & b->falling));
    for (uint8_t bit = 0; due; bit++, due >>= 1) {
        if ((due & 1u) && b->handlers[bit])
            b->handlers[bit]();
    }
}

ISR(PCINT0_vect) { run_change(0); }
ISR(PCINT1_vect) { run_change(1); }
ISR(PCINT2_vect) { run_change(2); }

static void attach_change(uint8_t line, uint8_t edge, irq_handler handler)
{
    uint8_t bank = line >> 4;
    uint8_t bit = (uint8_t)_BV(line & 7u);
    change_bank *b = &banks[bank];
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        *bank_mask(bank) &= (uint8_t)~bit;
        b->handlers[line & 7u] = handler;
        b->rising = (uint8_t)((b->rising & ~bit) | ((edge & IRQ_RISING) ? bit : 0));
        b->falling = (uint8_t)((b->falling & ~bit) | ((edge & IRQ_FALLING) ? bit : 0));
        /* Start from the present level, so the first interrupt compares with something real. */
        b->last = (uint8_t)((b->last & ~bit) | (bank_levels(bank) & bit));
        *bank_mask(bank) |= bit;
        PCICR = (uint8_t)(PCICR | _BV(bank));
    }
}

void irq_attach_pin(uint8_t pin, uint8_t edge, irq_handler handler)
{
    if (edge < IRQ_RISING || edge > IRQ_LOW)
        return;
    if (handler == NULL) {
        irq_detach_pin(pin);
        return;
    }
    uint8_t line = int_line(pin);
    if (line != NO_LINE) {
        attach_int(line, edge, handler);
        return;
    }
    line = change_line(pin);
    /* Pin-change interrupts have no level mode. */
    if (line != NO_LINE && edge != IRQ_LOW)
        attach_change(line, edge, handler);
}

void irq_detach_pin(uint8_t pin)
{
    uint8_t line = int_line(pin);
    if (line != NO_LINE) {
        ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
            EIMSK &= (uint8_t)~_BV(line);
            int_handlers[line] = NULL;
        }
        return;
    }
    line = change_line(pin);
    if (line == NO_LINE)
        return;
    uint8_t bank = line >> 4;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        *bank_mask(bank) &= (uint8_t)~_BV(line & 7u);
        banks[bank].handlers[line & 7u] = NULL;
        if (*bank_mask(bank) == 0)
            PCICR &= (uint8_t)~_BV(bank);
    }
}
