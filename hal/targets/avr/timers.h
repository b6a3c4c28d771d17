/* The timers' register blocks and their default PWM set-up, shared by hal_init, gpio, pwm and
 * the periodic interrupt; internal to the AVR target. */
#ifndef SEAR_HAL_AVR_TIMERS_H
#define SEAR_HAL_AVR_TIMERS_H

#include <stdint.h>

/* Timers 1, 3, 4 and 5 lay out their registers identically from TCCRnA on (datasheet, Register
 * Summary: TCCRnA, TCCRnB, TCCRnC, reserved, TCNTn, ICRn, OCRnA, OCRnB, OCRnC), and so do the
 * bit positions within them, so one overlay and timer1's bit names serve all four. */
typedef struct {
    uint8_t tccra, tccrb, tccrc, reserved;
    uint16_t tcnt, icr, ocr[3];
} timer16_regs;

/* Timers 0 and 2: TCCRnA, TCCRnB, TCNTn, OCRnA, OCRnB. */
typedef struct {
    uint8_t tccra, tccrb, tcnt, ocr[2];
} timer8_regs;

/* COMnx1:0 of channel 0 (A), 1 (B) or 2 (C) in TCCRnA: bits 7:6, 5:4, 3:2 in every timer. */
#define TIMER_COM_BITS(channel) (uint8_t)(0xC0u >> (2u * (channel)))
#define TIMER_COM_CLEAR_ON_MATCH(channel) (uint8_t)(0x80u >> (2u * (channel)))

/* The 50 Hz servo frame: fast PWM with TOP = ICRn (mode 14), clk/8 = 0.5 us per count. */
#define TIMER_SERVO_TOP 39999u

volatile uint8_t *hal_avr_timer_tccra(uint8_t timer);   /* timers 0..5 */

/* Shared by pwm_write and servo_write_us (pwm.c). A 16-bit timer is in the servo frame when WGMn3
 * is set: the PWM default (mode 1) and the periodic interrupt's CTC (mode 4) both leave it clear. */
uint8_t hal_avr_in_servo_frame(volatile timer16_regs *t);
/* duty/255 of the 40000-count frame, as the high time of OCRn + 1 counts in fast PWM. */
uint16_t hal_avr_servo_frame_ocr(uint8_t duty);
/* DDRx only: pin_mode would disconnect the channel first, and a running servo pulse or PWM
 * period would be cut short on every update. */
void hal_avr_timer_pin_output(uint8_t pin);
/* The channel's output compare drives its pin: cleared on match, as non-inverting PWM. */
void hal_avr_timer_connect(uint8_t timer, uint8_t channel);
volatile timer16_regs *hal_avr_timer16(uint8_t timer);  /* 1, 3, 4, 5; NULL otherwise */
volatile timer8_regs *hal_avr_timer8(uint8_t timer);    /* 0, 2; NULL otherwise */

/* Timers 1..5 to the Arduino core's analogWrite set-up: 8-bit phase-correct PWM at clk/64,
 * 490 Hz, every output disconnected. */
void hal_avr_timers_init(void);
void hal_avr_timer16_pwm_default(uint8_t timer);

/* Timer0: fast PWM at clk/64 (976 Hz on pins 4 and 13) whose overflow interrupt drives millis
 * and micros; in time.c, beside that interrupt, so linking hal_init always links the handler. */
void hal_avr_time_start(void);

#endif
