/* HAL-level test firmware for both engines: pings an HC-SR04 (TRIG on pin 24, ECHO on pin 10)
 * 60 ms after each echo (the sensor's measurement cycle) with the datasheet's 10 us trigger pulse and times the echo with pulse_in(). */
#include <hal/hal.h>

#define TRIG 24
#define ECHO 10

int main(void) {
  hal_init();
  pin_mode(TRIG, OUTPUT);
  pin_mode(ECHO, INPUT);
  for (;;) {
    digital_write(TRIG, HIGH);
    delay_us(10);
    digital_write(TRIG, LOW);
    (void)pulse_in(ECHO, HIGH, 30000);
    delay_ms(60);
  }
}
