/* Obstacle avoider for a two-wheeled rover: two Sharp GP2D12 rangers looking ahead-left and
 * ahead-right on ADC channels 0 and 1, a GP2D15 looking straight ahead on pin 22, a bump switch
 * on pin 2 (interrupt), and two DC motors on an Arduino Motor Shield R3 (PWM, direction, brake).
 * Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include <hal/hal.h>
#include <stdio.h>

#define IR_LEFT_CHANNEL 0
#define IR_RIGHT_CHANNEL 1
#define IR_FRONT_PIN 22 /* GP2D15: HIGH while something is within about 24 cm */
#define BUMP_PIN 2      /* switch to ground, closes on contact */

/* Motor Shield R3: channel A drives the left motor, channel B the right one. */
#define LEFT_PWM 3
#define LEFT_DIR 12
#define LEFT_BRAKE 9
#define RIGHT_PWM 11
#define RIGHT_DIR 13
#define RIGHT_BRAKE 8

#define CRUISE 150     /* PWM duty of 255 */
#define TURN 130
#define NEAR_CM 30     /* turn away below this */
#define VEER_CM 55     /* steer away below this */
#define CLEAR_MARGIN_CM 10 /* stop veering only this far beyond VEER_CM, or it would dither */
#define FAR_CM 80      /* the GP2D12's range ends here */

enum { CRUISING, VEERING_LEFT, VEERING_RIGHT, TURNING_LEFT, TURNING_RIGHT };
static const char *const state_names[] = {"cruising", "veering left", "veering right", "turning left",
                                          "turning right"};

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

/* Distance from a GP2D12 reading (10-bit, 5 V reference), the usual fit to the datasheet's curve:
 * cm = 6787 / (code - 3) - 4, good over 10..80 cm. */
static uint8_t ir_cm(uint8_t channel) {
  const uint16_t code = adc_read(channel);
  if (code < 84) return FAR_CM;
  const uint16_t cm = (uint16_t)(6787u / (code - 3u) - 4u);
  return (uint8_t)(cm > FAR_CM ? FAR_CM : cm);
}

static void say(const char *text) { uart_print(0, text); }

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  pin_mode(LEFT_DIR, OUTPUT);
  pin_mode(LEFT_BRAKE, OUTPUT);
  pin_mode(RIGHT_DIR, OUTPUT);
  pin_mode(RIGHT_BRAKE, OUTPUT);
  pin_mode(IR_FRONT_PIN, INPUT);
  pin_mode(BUMP_PIN, INPUT_PULLUP);
  irq_attach_pin(BUMP_PIN, IRQ_FALLING, on_bump);
  say("avoider: ready\r\n");
  delay_ms(100); /* the rangers' first measurement is ready after one 38 ms cycle */

  uint32_t next_report = 0;
  uint8_t state = CRUISING;
  char line[64];
  for (;;) {
    const uint8_t left = ir_cm(IR_LEFT_CHANNEL);
    const uint8_t right = ir_cm(IR_RIGHT_CHANNEL);
    const uint8_t front = digital_read(IR_FRONT_PIN);

    uint8_t next;
    if (bumped) {
      say("bump: backing off\r\n");
      drive(-TURN, -TURN);
      delay_ms(400);
      drive(-TURN, TURN);
      delay_ms(350);
      bumped = 0;
      next = CRUISING;
    } else if (front || left < NEAR_CM || right < NEAR_CM) {
      /* Turn on the spot away from the nearer side, and keep turning the same way until clear,
       * so that a corner cannot make it dither. */
      if (state == TURNING_LEFT || state == TURNING_RIGHT) next = state;
      else next = left < right ? TURNING_RIGHT : TURNING_LEFT;
    } else if (left < VEER_CM || (state == VEERING_RIGHT && left < VEER_CM + CLEAR_MARGIN_CM)) {
      next = VEERING_RIGHT;
    } else if (right < VEER_CM || (state == VEERING_LEFT && right < VEER_CM + CLEAR_MARGIN_CM)) {
      next = VEERING_LEFT;
    } else {
      next = CRUISING;
    }
    switch (next) {
      case TURNING_LEFT: drive(-TURN, TURN); break;
      case TURNING_RIGHT: drive(TURN, -TURN); break;
      case VEERING_LEFT: drive(CRUISE / 3, CRUISE); break;
      case VEERING_RIGHT: drive(CRUISE, CRUISE / 3); break;
      default: drive(CRUISE, CRUISE); break;
    }
    if (next != state) {
      snprintf(line, sizeof line, "%s (L %u cm, R %u cm, front %s)\r\n", state_names[next], left, right,
               front ? "near" : "clear");
      say(line);
      state = next;
    }

    if (millis() >= next_report) {
      next_report += 10000;
      snprintf(line, sizeof line, "still going: L %u cm, R %u cm, front %s\r\n", left, right,
               front ? "near" : "clear");
      say(line);
    }
    delay_ms(20);
  }
}
