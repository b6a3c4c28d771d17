/* analogWrite-style PWM on the timer pins and 50 Hz servo pulses: from the hardware on the pins of
 * timers 1, 3 and 4, sharing each timer between the two, and from timer5's interrupt on any
 * other pin (soft_servo.c). */
#include <hal/pwm.h>

#include <hal/gpio.h>

#include "pin_map.h"
#include "soft_servo.h"
#include "timers.h"

#include <avr/io.h>
#include <stddef.h>
#include <util/atomic.h>

/* A servo pin of timers 1, 3 or 4 switches its whole timer to the 50 Hz frame; PWM on that
 * timer's other pins then runs at 50 Hz too, with its duty kept. The hardware makes those pulses
 * exactly, with no interrupt. Timer5 (pins 44..46) is the shared one: it makes the pulses of
 * every other servo pin, 44..46 included, or runs irq_timer_start; while it does either, PWM on
 * 44..46 is a plain output (pwm_write gives LOW below 128 and HIGH from 128). */

/* A 16-bit timer is in the servo frame when WGMn3 is set: the PWM default (mode 1) and the
 * periodic interrupt's CTC (mode 4) both leave it clear. */
static uint8_t in_servo_frame(volatile timer16_regs *t)
{
    return (t->tccrb & _BV(WGM13)) != 0;
}

/* irq_timer_start (compare A) or the software servos (compare B) own timer5 while their
 * interrupt is enabled. */
static uint8_t timer5_taken(uint8_t timer)
{
    return timer == 5 && (TIMSK5 & (_BV(OCIE5A) | _BV(OCIE5B)));
}

/* duty/255 of the 40000-count frame, as the high time of OCRn + 1 counts in fast PWM. */
static uint16_t servo_frame_ocr(uint8_t duty)
{
    return (uint16_t)((uint32_t)duty * (TIMER_SERVO_TOP + 1u) / 255u - 1u);
}

/* DDRx only: pin_mode would disconnect the channel first, and a running servo pulse or PWM
 * period would be cut short on every update. */
static void make_output(uint8_t pin)
{
    pin_io io = hal_avr_pin_io(pin);
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        PIN_DDR(io) |= io.mask;
    }
}

static void connect(uint8_t timer, uint8_t channel)
{
    volatile uint8_t *tccra = hal_avr_timer_tccra(timer);
    *tccra = (uint8_t)((*tccra & ~TIMER_COM_BITS(channel)) | TIMER_COM_CLEAR_ON_MATCH(channel));
}

void pwm_write(uint8_t pin, uint8_t duty)
{
    uint8_t code = hal_avr_pin_timer(pin);
    if (code == PIN_NO_TIMER)
        return;
    uint8_t timer = PIN_TIMER_NUMBER(code);
    uint8_t channel = PIN_TIMER_CHANNEL(code);
    make_output(pin);
    /* The ends are plain levels: fast PWM (timer0) would still leave a one-count spike at 0,
     * and a taken timer5 has no PWM to give. */
    if (duty == 0 || duty == 255 || timer5_taken(timer)) {
        digital_write(pin, duty >= 128 ? HIGH : LOW);
        return;
    }
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        volatile timer16_regs *t16 = hal_avr_timer16(timer);
        if (t16)
            t16->ocr[channel] = in_servo_frame(t16) ? servo_frame_ocr(duty) : duty;
        else
            hal_avr_timer8(timer)->ocr[channel] = duty;
        connect(timer, channel);
    }
}

/* Mode 14 at clk/8: TOP = ICRn = 39999 gives 20 ms in 0.5 us counts. Channels already driving
 * PWM are rescaled from 8-bit duty (their OCRn) to the same fraction of the new frame. */
static void enter_servo_frame(volatile timer16_regs *t)
{
    t->tccrb = 0;
    t->icr = TIMER_SERVO_TOP;
    for (uint8_t channel = 0; channel < 3; channel++) {
        if (t->tccra & TIMER_COM_BITS(channel))
            t->ocr[channel] = servo_frame_ocr((uint8_t)t->ocr[channel]);
    }
    t->tccra = (uint8_t)((t->tccra & (TIMER_COM_BITS(0) | TIMER_COM_BITS(1) | TIMER_COM_BITS(2)))
                         | _BV(WGM11));
    t->tcnt = 0;
    t->tccrb = _BV(WGM13) | _BV(WGM12) | _BV(CS11);
}

void servo_write_us(uint8_t pin, uint16_t pulse_us)
{
    uint8_t code = hal_avr_pin_timer(pin);
    uint8_t timer = PIN_TIMER_NUMBER(code);
    uint8_t channel = PIN_TIMER_CHANNEL(code);
    volatile timer16_regs *t = code == PIN_NO_TIMER ? NULL : hal_avr_timer16(timer);
    if (t == NULL || timer == 5) {
        hal_avr_soft_servo_write(pin, pulse_us);
        return;
    }
    make_output(pin);
    if (pulse_us == 0) {
        digital_write(pin, LOW);
        return;
    }
    if (pulse_us > 20000u)
        pulse_us = 20000u;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        if (!in_servo_frame(t))
            enter_servo_frame(t);
        /* The output is high for OCRn + 1 counts of 0.5 us; OCRn is double-buffered in this
         * mode, so a new width starts with the next frame and no pulse is cut short. */
        t->ocr[channel] = (uint16_t)(pulse_us * 2u - 1u);
        connect(timer, channel);
    }
}
