/* The periodic interrupt of irq_timer_start, on timer5 in CTC mode. Timer5 also serves PWM on
 * pins 44..46, plain outputs while the periodic interrupt runs, and the software servo pulses
 * (soft_servo.c), which cannot share it. */
#include <hal/irq.h>
#include <hal/system.h>

#include "soft_servo.h"
#include "timers.h"

#include <avr/interrupt.h>
#include <avr/io.h>
#include <stddef.h>
#include <util/atomic.h>

#define MIN_PERIOD_US 16u
#define MAX_PERIOD_US 4194304UL /* 65536 counts at clk/1024, 64 us each */

static volatile irq_handler tick_handler;

ISR(TIMER5_COMPA_vect)
{
    irq_handler handler = tick_handler;
    if (handler)
        handler();
}

void irq_timer_start(uint32_t period_us, irq_handler handler)
{
    if (handler == NULL) {
        irq_timer_stop();
        return;
    }
    if (hal_avr_soft_servos_running())
        hal_refuse("irq_timer_start: timer5 makes the servo pulses of the pins without a 16-bit PWM timer");
    if (period_us < MIN_PERIOD_US)
        period_us = MIN_PERIOD_US;
    if (period_us > MAX_PERIOD_US)
        period_us = MAX_PERIOD_US;

    /* Timer5's prescalers (CS52:0 = 1..5) as powers of two: clk/1, /8, /64, /256, /1024. The
     * smallest whose count fits in 16 bits gives the finest period. */
    static const uint8_t shifts[5] = {0, 3, 6, 8, 10};
    uint32_t cycles = period_us * (F_CPU / 1000000UL);
    uint8_t select = 0;
    uint32_t counts;
    for (;;) {
        counts = (cycles + ((1UL << shifts[select]) >> 1)) >> shifts[select]; /* rounded */
        if (counts <= 65536UL || select == 4)
            break;
        select++;
    }

    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        TIMSK5 = 0;
        TCCR5B = 0;
        TCCR5A = 0; /* OC5A..C disconnected: pins 44..46 fall back to their PORTL bits */
        TCNT5 = 0;
        OCR5A = (uint16_t)(counts - 1u); /* CTC mode 4: a period is OCR5A + 1 counts */
        tick_handler = handler;
        TIFR5 = _BV(OCF5A);
        TIMSK5 = _BV(OCIE5A);
        TCCR5B = (uint8_t)(_BV(WGM52) | (select + 1u));
    }
}

void irq_timer_stop(void)
{
    uint8_t running;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        running = (TIMSK5 & _BV(OCIE5A)) != 0;
        TIMSK5 = 0;
        tick_handler = NULL;
    }
    /* Only a timer taken from PWM goes back to it: a stray stop must not reset pins 44..46. */
    if (running)
        hal_avr_timer16_pwm_default(5);
}
