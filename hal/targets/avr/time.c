/* millis/micros from timer0's overflow interrupt, and the delays built on them. Timer0 runs
 * exactly as in the Arduino core (fast PWM, clk/64), so pins 4 and 13 keep their 976 Hz PWM. */
#include <hal/time.h>

#include "timers.h"

#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/atomic.h>
#include <util/delay_basic.h>

/* One timer0 count is 64 / 16 MHz = 4 us; an overflow is 256 counts = 1024 us, i.e. 1 ms plus
 * 24 us, which millis carries in steps of 8 us so the sum stays exact. */
#define US_PER_COUNT 4u
#define FRACTION_STEP 3u  /* 24 us in 8 us units */
#define FRACTION_ONE_MS 125u

static volatile uint32_t overflows;
static volatile uint32_t milliseconds;
static volatile uint8_t fraction;

ISR(TIMER0_OVF_vect)
{
    uint32_t ms = milliseconds + 1;
    uint8_t f = (uint8_t)(fraction + FRACTION_STEP);
    if (f >= FRACTION_ONE_MS) {
        f = (uint8_t)(f - FRACTION_ONE_MS);
        ms++;
    }
    milliseconds = ms;
    fraction = f;
    overflows++;
}

void hal_avr_time_start(void)
{
    TCCR0B = 0;
    TCCR0A = _BV(WGM01) | _BV(WGM00);
    TCNT0 = 0;
    TIFR0 = _BV(TOV0);
    TIMSK0 = _BV(TOIE0);
    TCCR0B = _BV(CS01) | _BV(CS00);
}

uint32_t millis(void)
{
    uint32_t ms;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        ms = milliseconds;
    }
    return ms;
}

uint32_t micros(void)
{
    uint32_t count;
    uint8_t now;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        count = overflows;
        now = TCNT0;
        /* An overflow that happened since interrupts were disabled is still pending; if TCNT0
         * read 255 the overflow came after the read and must not be counted. */
        if ((TIFR0 & _BV(TOV0)) && now != 255)
            count++;
    }
    return ((count << 8) + now) * US_PER_COUNT;
}

static uint8_t interrupts_enabled(void)
{
    return (SREG & _BV(SREG_I)) != 0;
}

/* Below this a counted-cycle wait is finer than the 4 us clock; above it, watching the clock
 * absorbs the time interrupt handlers take, which counted cycles would add on top. */
#define CLOCK_WAIT_MIN_US 100u

/* Counting cycles instead of watching the clock: for short waits, and when interrupts are off
 * (in a handler), since the clock stands still then. Each _delay_loop_2 iteration is 4 cycles,
 * a quarter of a microsecond. */
static void spin_us(uint32_t us)
{
    while (us > 16000u) {
        _delay_loop_2(64000u);
        us -= 16000u;
    }
    if (us > 0)
        _delay_loop_2((uint16_t)(us * 4u));
}

void delay_us(uint32_t us)
{
    if (us < CLOCK_WAIT_MIN_US || !interrupts_enabled()) {
        spin_us(us);
        return;
    }
    /* Within one 4 us clock step of us, either way. */
    uint32_t start = micros();
    while ((uint32_t)(micros() - start) < us) {
    }
}

void delay_ms(uint32_t ms)
{
    if (!interrupts_enabled()) {
        while (ms-- > 0)
            spin_us(1000u);
        return;
    }
    /* Advancing start by whole milliseconds keeps the total exact however late each check is,
     * and avoids ms * 1000 overflowing after 71 minutes. */
    uint32_t start = micros();
    while (ms > 0) {
        if ((uint32_t)(micros() - start) >= 1000u) {
            ms--;
            start += 1000u;
        }
    }
}
