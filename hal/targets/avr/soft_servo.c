/* Servo pulses on any pin: timer5 counts freely at clk/8 (0.5 us) in normal mode, and its compare
 * B interrupt lowers the pin whose pulse ends and raises the next servo's, one after another, then
 * waits out the 20 ms frame; the way the Arduino Servo library pulses pins on the Mega. */
#include "soft_servo.h"

#include <hal/gpio.h>
#include <hal/system.h>

#include "pin_map.h"
#include "timers.h"

#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/atomic.h>

#define NONE 0xFFu
#define MIN_PULSE_US 400u
#define MAX_PULSE_US 2600u
/* After a frame the pulses overran (12 of 2600 us), the next starts this long after the last
 * pulse ended: 50 us, time enough to leave the interrupt first. */
#define OVERRUN_GAP_COUNTS 100u

/* A servo's PORTx and bit, resolved once so that the interrupt only stores; counts 0: its pulses
 * are stopped. */
typedef struct {
    volatile uint8_t *port;
    uint8_t mask;
    uint16_t counts;
} servo_slot;

static servo_slot slots[SOFT_SERVO_MAX];
static uint8_t slot_pin[SOFT_SERVO_MAX];
static uint8_t slot_count;

/* What the next compare does, prepared by the one before so that the interrupt's first stores
 * are the pins' edges: the pin whose pulse ends falls, then the next servo's pin rises. With no
 * pin to move, the stores go to a spare byte, so the edges always come the same few cycles after
 * the compare, whatever the interrupt's path: a width is its counts less the cycles from the
 * falling store to the rising one (11, 0.69 us, with avr-gcc -Os), the entry latency being the
 * same at both of its edges when nothing else holds interrupts off. */
static uint8_t spare;
static volatile uint8_t *fall_port = &spare, *rise_port = &spare;
static volatile uint8_t fall_mask, rise_mask;
static volatile uint8_t rising = NONE;    /* the slot the next compare raises */
static uint16_t rise_counts;              /* and its width when prepared */
static volatile uint8_t high_slot = NONE; /* the slot whose pulse is on */
static uint16_t frame_start;              /* the compare the frame began at */

static uint8_t first_active(uint8_t from)
{
    while (from < slot_count && slots[from].counts == 0)
        from++;
    return from < slot_count ? from : NONE;
}

/* The next compare raises `next` (NONE: nothing). */
static void prepare_rise(uint8_t next)
{
    rising = next;
    if (next == NONE) {
        rise_port = &spare;
        rise_mask = 0;
        return;
    }
    rise_port = slots[next].port;
    rise_mask = slots[next].mask;
    rise_counts = slots[next].counts;
}

ISR(TIMER5_COMPB_vect)
{
    *fall_port &= (uint8_t)~fall_mask;
    *rise_port |= rise_mask;
    uint8_t raised = rising;
    high_slot = raised;
    if (raised != NONE) {
        /* Its pulse ends after its width as it is now (a pulse stopped since it was prepared
         * keeps its turn's length, with the pin left LOW), and the next servo's starts there. */
        uint16_t counts = slots[raised].counts;
        OCR5B += counts ? counts : rise_counts;
        fall_port = rise_port;
        fall_mask = rise_mask;
        prepare_rise(first_active((uint8_t)(raised + 1u)));
        return;
    }
    /* The last pulse of the frame ended (or there was none): the next frame starts 20 ms after
     * this one did, or just after now if its pulses ran past that. */
    fall_port = &spare;
    fall_mask = 0;
    uint16_t used = (uint16_t)(OCR5B - frame_start);
    frame_start = used + OVERRUN_GAP_COUNTS <= SOFT_SERVO_FRAME_COUNTS
                      ? (uint16_t)(frame_start + SOFT_SERVO_FRAME_COUNTS)
                      : (uint16_t)(OCR5B + OVERRUN_GAP_COUNTS);
    OCR5B = frame_start;
    prepare_rise(first_active(0));
}

static uint8_t slot_of(uint8_t pin)
{
    for (uint8_t i = 0; i < slot_count; i++) {
        if (slot_pin[i] == pin)
            return i;
    }
    return NONE;
}

/* Timer5 in normal mode at clk/8, the first frame starting a moment from now. Its PWM outputs on
 * 44..46 are disconnected, as the library's set-up does. */
static void start_timer5(void)
{
    TCCR5B = 0;
    TCCR5A = 0;
    TCNT5 = 0;
    high_slot = NONE;
    fall_port = &spare;
    fall_mask = 0;
    frame_start = OVERRUN_GAP_COUNTS;
    OCR5B = frame_start;
    prepare_rise(first_active(0));
    TIFR5 = _BV(OCF5B);
    TIMSK5 = _BV(OCIE5B);
    TCCR5B = _BV(CS51);
}

/* A stopped slot another pin may take: no pulses, and none on the wire. */
static uint8_t free_slot(void)
{
    for (uint8_t i = 0; i < slot_count; i++) {
        if (slots[i].counts == 0 && high_slot != i && rising != i)
            return i;
    }
    return slot_count < SOFT_SERVO_MAX ? slot_count : NONE;
}

static void stop(uint8_t i)
{
    uint8_t any = 0;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        slots[i].counts = 0;
        if (rising == i)
            rise_mask = 0; /* its turn comes and goes with the pin left LOW */
        for (uint8_t k = 0; k < slot_count; k++)
            if (slots[k].counts)
                any = 1;
    }
    /* A pulse on the pin ends at its compare, not cut short (with interrupts on to let it). */
    if (SREG & _BV(SREG_I)) {
        while (high_slot == i) {
        }
    }
    if (!any) {
        /* No pulse is left to raise: timer5 goes back to PWM. */
        TIMSK5 = 0;
        hal_avr_timer16_pwm_default(5);
    }
}

void hal_avr_soft_servo_write(uint8_t pin, uint16_t pulse_us)
{
    pin_io io = hal_avr_pin_io(pin);
    if (!io.mask)
        return;
    uint8_t i = slot_of(pin);
    if (pulse_us == 0) {
        if (i != NONE && slots[i].counts)
            stop(i);
        digital_write(pin, LOW);
        return;
    }
    if (TIMSK5 & _BV(OCIE5A))
        hal_refuse("servo_write_us on a pin without a 16-bit PWM timer: timer5 makes those pulses, and "
                   "irq_timer_start holds it");
    if (pulse_us < MIN_PULSE_US)
        pulse_us = MIN_PULSE_US;
    if (pulse_us > MAX_PULSE_US)
        pulse_us = MAX_PULSE_US;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        if (i == NONE) {
            i = free_slot();
            if (i == NONE)
                hal_refuse("servo_write_us: more than 12 pins without a 16-bit PWM timer at once");
            /* LOW until its turn in the frame raises it. */
            PIN_PORT(io) &= (uint8_t)~io.mask;
            slots[i].port = &PIN_PORT(io);
            slots[i].mask = io.mask;
            slot_pin[i] = pin;
            if (i == slot_count)
                slot_count++;
        }
        PIN_DDR(io) |= io.mask;
        /* A pulse already on keeps the compare it was given: the new width starts with the
         * pin's next pulse. */
        slots[i].counts = (uint16_t)(pulse_us * 2u);
        if (!hal_avr_soft_servos_running())
            start_timer5();
    }
}
