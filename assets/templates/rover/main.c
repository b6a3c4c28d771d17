/* @NAME@: an empty rover. Two DC motors on an Arduino Motor Shield R3 (PWM, direction, brake),
 * nothing else wired yet; the loop drives a square by time alone (dead reckoning at its
 * crudest: watch the square drift in trace_rover.csv, then add encoders or an IMU).
 * The same file builds for SEAR's simulator and for an ATmega2560: only <hal/hal.h> separates it
 * from the hardware. int is 16 bits on the AVR, so every wider value says so. */
#include <hal/hal.h>
#include <stdio.h>

/* Motor Shield R3: channel A drives the left motor, channel B the right one. */
#define LEFT_PWM 3
#define LEFT_DIR 12
#define LEFT_BRAKE 9
#define RIGHT_PWM 11
#define RIGHT_DIR 13
#define RIGHT_BRAKE 8

#define SPEED 150     /* PWM duty of 255: about 0.4 m/s on the bundled rover */
#define SIDE_MS 2000  /* one side of the square, about 0.8 m */
#define TURN_MS 430   /* a quarter turn on the spot at SPEED; tune it on your floor */
#define PAUSE_MS 300  /* let the rover come to rest between moves */

/* One motor: speed -255..255, negative backwards. */
static void motor(uint8_t pwm_pin, uint8_t dir_pin, uint8_t brake_pin, int16_t speed) {
  digital_write(brake_pin, LOW);
  digital_write(dir_pin, speed >= 0 ? HIGH : LOW);
  pwm_write(pwm_pin, (uint8_t)(speed >= 0 ? speed : -speed));
}

static void drive(int16_t left, int16_t right) {
  motor(LEFT_PWM, LEFT_DIR, LEFT_BRAKE, left);
  motor(RIGHT_PWM, RIGHT_DIR, RIGHT_BRAKE, right);
}

int main(void) {
  /* ---- setup: runs once ---- */
  hal_init();
  uart_begin(0, 115200); /* UART 0 is the console: sear's rover.main.console.log, the board's USB serial */
  pin_mode(LEFT_DIR, OUTPUT);
  pin_mode(LEFT_BRAKE, OUTPUT);
  pin_mode(RIGHT_DIR, OUTPUT);
  pin_mode(RIGHT_BRAKE, OUTPUT);
  uart_print(0, "@NAME@: ready\r\n");

  /* ---- loop: runs forever ---- */
  uint16_t side = 0;
  char line[40];
  for (;;) {
    ++side;
    snprintf(line, sizeof line, "side %u at %lu ms\r\n", side, (unsigned long)millis());
    uart_print(0, line);
    drive(SPEED, SPEED);
    delay_ms(SIDE_MS);
    drive(0, 0);
    delay_ms(PAUSE_MS);
    drive(-SPEED, SPEED); /* left, counter-clockwise seen from above */
    delay_ms(TURN_MS);
    drive(0, 0);
    delay_ms(PAUSE_MS);
  }
}
