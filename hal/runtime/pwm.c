/* PWM and servo pulses: the simulator sees the duty or pulse width, not each edge. */
#include <hal/gpio.h>
#include <hal/pwm.h>

#include "board.h"
#include "mcu.h"

static void make_output(uint8_t pin, int64_t now) {
  if (sear_mcu.mode[pin] == OUTPUT) return;
  sear_mcu.mode[pin] = OUTPUT;
  mcu_emit(SEAR_EVENT_PIN_MODE, pin, OUTPUT, now);
  mcu_emit(SEAR_EVENT_PIN, pin, sear_mcu.latch[pin], now);
}

void pwm_write(uint8_t pin, uint8_t duty) {
  const int64_t now = mcu_enter(SEAR_CALL_pwm_write);
  mcu_check_pin(pin, "pwm_write");
  if (!board_has_pwm(pin)) mcu_fatal("pwm_write(%u): on the ATmega2560 board only pins 2..13 and 44..46 have PWM", pin);
  make_output(pin, now);
  /* Full off and full on are plain levels, as analogWrite() does on the board. */
  if (duty == 0 || duty == 255) {
    const uint8_t level = duty ? HIGH : LOW;
    if (sear_mcu.pwm[pin] || sear_mcu.latch[pin] != level) mcu_emit(SEAR_EVENT_PIN, pin, level, now);
    sear_mcu.pwm[pin] = 0;
    sear_mcu.latch[pin] = level;
    return;
  }
  sear_mcu.pwm[pin] = 1;
  mcu_emit(SEAR_EVENT_PWM, pin, duty, now);
}

void servo_write_us(uint8_t pin, uint16_t pulse_us) {
  const int64_t now = mcu_enter(SEAR_CALL_servo_write_us);
  mcu_check_pin(pin, "servo_write_us");
  /* Any pin: Arduino's Servo library makes the pulses from a timer's compare interrupt. */
  if (pulse_us != 0 && (pulse_us < 400 || pulse_us > 2600))
    mcu_fatal("servo_write_us(%u, %u): a servo pulse is 400..2600 us (0 stops the pulses)", pin, pulse_us);
  make_output(pin, now);
  mcu_emit(SEAR_EVENT_SERVO, pin, pulse_us, now);
}
