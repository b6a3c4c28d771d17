/* The PWM timers' start-up configuration and the lookup of each timer's registers by number,
 * so that pwm.c and the periodic interrupt can share timers without knowing each other. */
#include "timers.h"

#include <avr/io.h>
#include <stddef.h>
#include <util/atomic.h>

volatile uint8_t *hal_avr_timer_tccra(uint8_t timer)
{
    switch (timer) {
    case 0: return &TCCR0A;
    case 1: return &TCCR1A;
    case 2: return &TCCR2A;
    case 3: return &TCCR3A;
    case 4: return &TCCR4A;
    default: return &TCCR5A;
    }
}

volatile timer16_regs *hal_avr_timer16(uint8_t timer)
{
    if (timer == 0 || timer == 2 || timer > 5)
        return NULL;
    return (volatile timer16_regs *)hal_avr_timer_tccra(timer);
}

volatile timer8_regs *hal_avr_timer8(uint8_t timer)
{
    if (timer != 0 && timer != 2)
        return NULL;
    return (volatile timer8_regs *)hal_avr_timer_tccra(timer);
}

void hal_avr_timer16_pwm_default(uint8_t timer)
{
    volatile timer16_regs *t = hal_avr_timer16(timer);
    if (!t)
        return;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        t->tccrb = 0; /* stopped while the mode changes, so no half-configured period runs */
        t->tccra = _BV(WGM10);
        t->tcnt = 0;
        t->ocr[0] = t->ocr[1] = t->ocr[2] = 0;
        t->tccrb = _BV(CS11) | _BV(CS10);
    }
}

void hal_avr_timers_init(void)
{
    /* Timer2 has its own prescaler table: CS22 alone is clk/64 there. */
    TCCR2B = 0;
    TCCR2A = _BV(WGM20);
    TCCR2B = _BV(CS22);
    hal_avr_timer16_pwm_default(1);
    hal_avr_timer16_pwm_default(3);
    hal_avr_timer16_pwm_default(4);
    hal_avr_timer16_pwm_default(5);
}
