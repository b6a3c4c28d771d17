/* servo_write_us: 50 Hz pulses from the hardware on the pins of timers 1, 3 and 4 (2, 3, 5..8, 11,
 * 12), exact and with no interrupt, and from timer5's interrupt on any other pin (soft_servo.c).
 * Its own file, so that a firmware that never calls it links neither that interrupt nor its
 * state. */
#include <hal/pwm.h>

#include <hal/gpio.h>

#include "pin_map.h"
#include "soft_servo.h"
#include "timers.h"

#include <avr/io.h>
#include <stddef.h>
#include <util/atomic.h>

/* Mode 14 at clk/8: TOP = ICRn = 39999 gives 20 ms in 0.5 us counts. Channels already driving
 * PWM are rescaled from 8-bit duty (their OCRn) to the same fraction of the new frame. */
static void enter_servo_frame(volatile timer16_regs *t)
{
    t->tccrb = 0;
    t->icr = TIMER_SERVO_TOP;
    for (uint8_t channel = 0; channel < 3; channel++) {
        if (t->tccra & TIMER_COM_BITS(channel))
            t->ocr[channel] = hal_avr_servo_frame_ocr((uint8_t)t->ocr[channel]);
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
    hal_avr_timer_pin_output(pin);
    if (pulse_us == 0) {
        digital_write(pin, LOW);
        return;
    }
    if (pulse_us > 20000u)
        pulse_us = 20000u;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        if (!hal_avr_in_servo_frame(t))
            enter_servo_frame(t);
        /* The output is high for OCRn + 1 counts of 0.5 us; OCRn is double-buffered in this
         * mode, so a new width starts with the next frame and no pulse is cut short. */
        t->ocr[channel] = (uint16_t)(pulse_us * 2u - 1u);
        hal_avr_timer_connect(timer, channel);
    }
}
