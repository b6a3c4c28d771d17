/* Two DC motors on an Arduino Motor Shield R3, as every rover example wires them: channel A drives
 * the left motor (PWM 3, direction 12, brake 9), channel B the right one (PWM 11, 13, 8). */
#ifndef FIRMWARE_MOTOR_SHIELD_H
#define FIRMWARE_MOTOR_SHIELD_H
#include <stdint.h>

#define MOTOR_LEFT_PWM 3
#define MOTOR_LEFT_DIR 12
#define MOTOR_LEFT_BRAKE 9
#define MOTOR_RIGHT_PWM 11
#define MOTOR_RIGHT_DIR 13
#define MOTOR_RIGHT_BRAKE 8

/* Direction and brake pins to outputs; the motors stay as they are until motors_drive(). */
void motors_begin(void);
/* Duties -255..255 each, negative backwards (beyond: full duty); releases the brakes. */
void motors_drive(int16_t left, int16_t right);
/* Both PWMs off and both brakes on. */
void motors_brake(void);

#endif
