/* The Motor Shield R3's two channels: see motor_shield.h. */
#include "motor_shield.h"

#include <hal/hal.h>

void motors_begin(void) {
  pin_mode(MOTOR_LEFT_DIR, OUTPUT);
  pin_mode(MOTOR_LEFT_BRAKE, OUTPUT);
  pin_mode(MOTOR_RIGHT_DIR, OUTPUT);
  pin_mode(MOTOR_RIGHT_BRAKE, OUTPUT);
}

static void motor(uint8_t pwm_pin, uint8_t dir_pin, uint8_t brake_pin, int16_t speed) {
  digital_write(brake_pin, LOW);
  digital_write(dir_pin, speed >= 0 ? HIGH : LOW);
  /* Full duty beyond +-255: a steering sum past it must not wrap to a crawl. */
  const int duty = speed >= 0 ? speed : -speed;
  pwm_write(pwm_pin, (uint8_t)(duty > 255 ? 255 : duty));
}

void motors_drive(int16_t left, int16_t right) {
  motor(MOTOR_LEFT_PWM, MOTOR_LEFT_DIR, MOTOR_LEFT_BRAKE, left);
  motor(MOTOR_RIGHT_PWM, MOTOR_RIGHT_DIR, MOTOR_RIGHT_BRAKE, right);
}

void motors_brake(void) {
  pwm_write(MOTOR_LEFT_PWM, 0);
  pwm_write(MOTOR_RIGHT_PWM, 0);
  digital_write(MOTOR_LEFT_BRAKE, HIGH);
  digital_write(MOTOR_RIGHT_BRAKE, HIGH);
}
