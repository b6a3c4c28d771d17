// Servo on the HAL's servo pulses, with the library's bookkeeping (indices, min/max in 4 us steps,
// angle or microseconds) and its claim on Timer5.
#include <Arduino.h>
#include <Servo.h>
#include <hal/pwm.h>

#include "servo_timer.hpp"

namespace {

struct Channel {
  uint8_t pin;
  bool active;
  uint16_t pulse_us;
};

Channel channels[MAX_SERVOS];
uint8_t servo_count = 0;
bool timer5_taken = false;

int min_us(int8_t m) { return MIN_PULSE_WIDTH - m * 4; }
int max_us(int8_t m) { return MAX_PULSE_WIDTH - m * 4; }

}  // namespace

bool sear_servo_timer5_taken() { return timer5_taken; }

Servo::Servo() : min_(0), max_(0) {
  if (servo_count < MAX_SERVOS) {
    index_ = servo_count++;
    channels[index_].pulse_us = DEFAULT_PULSE_WIDTH;
  } else {
    index_ = INVALID_SERVO;
  }
}

uint8_t Servo::attach(int pin) { return attach(pin, MIN_PULSE_WIDTH, MAX_PULSE_WIDTH); }

uint8_t Servo::attach(int pin, int min, int max) {
  if (index_ >= MAX_SERVOS) return INVALID_SERVO;
  pinMode(static_cast<uint8_t>(pin), OUTPUT);
  channels[index_].pin = static_cast<uint8_t>(pin);
  min_ = static_cast<int8_t>((MIN_PULSE_WIDTH - min) / 4);
  max_ = static_cast<int8_t>((MAX_PULSE_WIDTH - max) / 4);
  // The first servo of each block of 12 starts its timer; index 0's is Timer5 on the Mega, whose
  // set-up disconnects OC5A..C, so PWM on 44..46 stops.
  if (!timer5_taken) {
    timer5_taken = true;
    sear_servo_take_timer5();
  }
  channels[index_].active = true;
  servo_write_us(channels[index_].pin, channels[index_].pulse_us);
  return index_;
}

void Servo::detach() {
  if (index_ >= MAX_SERVOS || !channels[index_].active) return;
  channels[index_].active = false;
  servo_write_us(channels[index_].pin, 0);
}

void Servo::write(int value) {
  if (value < MIN_PULSE_WIDTH) {
    value = constrain(value, 0, 180);
    value = static_cast<int>(map(value, 0, 180, min_us(min_), max_us(max_)));
  }
  writeMicroseconds(value);
}

// The library clamps to the attach() limits; its timer counts in 0.5 us ticks less a 12-tick
// compensation for the interrupt's own time, which the pin's pulse then regains.
void Servo::writeMicroseconds(int value) {
  if (index_ >= MAX_SERVOS) return;
  value = constrain(value, min_us(min_), max_us(max_));
  channels[index_].pulse_us = static_cast<uint16_t>(value);
  if (channels[index_].active) servo_write_us(channels[index_].pin, static_cast<uint16_t>(value));
}

int Servo::read() { return static_cast<int>(map(readMicroseconds() + 1, min_us(min_), max_us(max_), 0, 180)); }

int Servo::readMicroseconds() { return index_ < MAX_SERVOS ? channels[index_].pulse_us : 0; }

bool Servo::attached() { return index_ < MAX_SERVOS && channels[index_].active; }
