/* @NAME@: an obstacle avoider for a two-wheeled rover. Two Sharp GP2D12 rangers look ahead-left
 * and ahead-right (ADC 0 and 1), a bump switch closes to ground on contact (pin 2, interrupt), and
 * the motors hang on an Arduino Motor Shield R3 (PWM, direction, brake).
 * The same file builds for SEAR's simulator and for an ATmega2560: only <hal/hal.h> separates it
 * from the hardware. int is 16 bits on the AVR, so every wider value says so. */
#include <hal/hal.h>
#include <stdio.h>

#define IR_LEFT_CHANNEL 0
#define IR_RIGHT_CHANNEL 1
#define BUMP_PIN 2

/* Motor Shield R3: channel A drives the left motor, channel B the right one. */
#define LEFT_PWM 3
#define LEFT_DIR 12
#define LEFT_BRAKE 9
#define RIGHT_PWM 11
#define RIGHT_DIR 13
#define RIGHT_BRAKE 8

#define CRUISE 150 /* PWM duty of 255 */
#define TURN 130
#define NEAR_CM 35 /* turn on the spot below this */
#define VEER_CM 60 /* steer away below this */
#define FAR_CM 80  /* the GP2D12 sees no further */

static volatile uint8_t bumped;

static void on_bump(void) { bumped = 1; }

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

/* Centimetres from a GP2D12 reading (10 bits, 5 V reference), the usual fit to the datasheet's
 * curve: cm = 6787 / (code - 3) - 4, good over 10..80 cm. */
static uint8_t ir_cm(uint8_t channel) {
  const uint16_t code = adc_read(channel);
  if (code < 84) return FAR_CM;
  const uint16_t cm = (uint16_t)(6787u / (code - 3u) - 4u);
  return (uint8_t)(cm > FAR_CM ? FAR_CM : cm);
}

int main(void) {
  /* ---- setup: runs once ---- */
  hal_init();
  uart_begin(0, 115200); /* UART 0 is the console: sear's rover.main.console.log, the board's USB serial */
  pin_mode(LEFT_DIR, OUTPUT);
  pin_mode(LEFT_BRAKE, OUTPUT);
  pin_mode(RIGHT_DIR, OUTPUT);
  pin_mode(RIGHT_BRAKE, OUTPUT);
  pin_mode(BUMP_PIN, INPUT_PULLUP);
  irq_attach_pin(BUMP_PIN, IRQ_FALLING, on_bump);
  uart_print(0, "@NAME@: ready\r\n");
  delay_ms(100); /* a GP2D12's first measurement is ready after one 38 ms cycle */

  /* ---- loop: runs forever ---- */
  uint32_t next_report = 0;
  char line[48];
  for (;;) {
    const uint8_t left = ir_cm(IR_LEFT_CHANNEL);
    const uint8_t right = ir_cm(IR_RIGHT_CHANNEL);

    if (bumped) { /* back off, turn away, carry on */
      uart_print(0, "bump: backing off\r\n");
      drive(-TURN, -TURN);
      delay_ms(400);
      drive(-TURN, TURN);
      delay_ms(350);
      bumped = 0;
    } else if (left < NEAR_CM || right < NEAR_CM) {
      if (left < right) drive(TURN, -TURN); /* turn right, away from the nearer side */
      else drive(-TURN, TURN);
    } else if (left < VEER_CM) {
      drive(CRUISE, CRUISE / 3);
    } else if (right < VEER_CM) {
      drive(CRUISE / 3, CRUISE);
    } else {
      drive(CRUISE, CRUISE);
    }

    if (millis() >= next_report) {
      next_report += 5000;
      snprintf(line, sizeof line, "L %u cm, R %u cm\r\n", left, right);
      uart_print(0, line);
    }
    delay_ms(20);
  }
}
