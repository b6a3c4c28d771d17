/* analogWrite-style PWM on the timer pins, sharing timers 1, 3 and 4 with the servo pulses of
 * servo.c, and timer5 with irq_timer_start and the software servos of soft_servo.c. */
#include <hal/pwm.h>

#include <hal/gpio.h>

#include "pin_map.h"
#include "timers.h"

#include <avr/io.h>
#include <stddef.h>
#include <util/atomic.h>

/* A timer in the servo frame runs PWM at 50 Hz, with its duty kept. Timer5 (pins 44..46) makes
 * the software servo pulses or runs irq_timer_start; while it does either, PWM on 44..46 is a
 * plain output (pwm_write gives LOW below 128 and HIGH from 128). */

uint8_t hal_avr_in_servo_frame(volatile timer16_regs *t)
{
    return (t->tccrb & _BV(WGM13)) != 0;
}

/* irq_timer_start (compare A) or the software servos (compare B) own timer5 while their
 * interrupt is enabled. */
static uint8_t timer5_taken(uint8_t timer)
{
    return timer == 5 && (TIMSK5 & (_BV(OCIE5A) | _BV(OCIE5B)));
}

uint16_t hal_avr_servo_frame_ocr(uint8_t duty)
{
    return (uint16_t)((uint32_t)duty * (TIMER_SERVO_TOP + 1u) / 255u - 1u);
}

void hal_avr_timer_pin_output(uint8_t pin)
{
    pin_io io = hal_avr_pin_io(pin);
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        PIN_DDR(io) |= io.mask;
    }
}

void hal_avr_timer_connect(uint8_t timer, uint8_t channel)
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
    hal_avr_timer_pin_output(pin);
    /* The ends are plain levels: fast PWM (timer0) would still leave a one-count spike at 0,
     * and a taken timer5 has no PWM to give. */
    if (duty == 0 || duty == 255 || timer5_taken(timer)) {
        digital_write(pin, duty >= 128 ? HIGH : LOW);
        return;
    }
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        volatile timer16_regs *t16 = hal_avr_timer16(timer);
        if (t16)
            t16->ocr[channel] = hal_avr_in_servo_frame(t16) ? hal_avr_servo_frame_ocr(duty) : duty;
        else
            hal_avr_timer8(timer)->ocr[channel] = duty;
        hal_avr_timer_connect(timer, channel);
    }
}
