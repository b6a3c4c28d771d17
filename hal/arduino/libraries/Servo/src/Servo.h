/* Arduino's Servo library for the simulated build: up to 48 servos on any pins, each a 50 Hz
 * pulse (the HAL's servo_write_us). As on the Mega, the first servo takes Timer5, after which
 * analogWrite() on pins 44, 45 and 46 is refused, since on the chip their PWM stops. */
#ifndef Servo_h
#define Servo_h

#include <stdint.h>

#define MIN_PULSE_WIDTH 544
#define MAX_PULSE_WIDTH 2400
#define DEFAULT_PULSE_WIDTH 1500
#define REFRESH_INTERVAL 20000
#define SERVOS_PER_TIMER 12
#define MAX_SERVOS 48
#define INVALID_SERVO 255

class Servo {
 public:
  Servo();
  uint8_t attach(int pin);
  uint8_t attach(int pin, int min, int max);
  void detach();
  void write(int value); /* below 544: an angle 0..180; else a pulse in microseconds */
  void writeMicroseconds(int value);
  int read();
  int readMicroseconds();
  bool attached();

 private:
  uint8_t index_;
  int8_t min_; /* as the library: (544 - min) / 4, so that min and max fit a byte */
  int8_t max_;
};

#endif
