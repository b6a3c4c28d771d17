/* Dead reckoning from wheel encoders: a quadrature encoder on each wheel (left A/B on pins 64/65,
 * right on 66/67, i.e. A10..A13, all pin-change interrupts) is decoded on every edge of both
 * channels, and the counts are integrated into a differential-drive pose. The rover drives a 1 m
 * square by that pose alone and prints it on the way.
 * Encoders: 360 counts per wheel turn, a count being one edge of either channel (90 cycles per
 * channel), and A leads B while the wheel turns forward. Geometry from assets/robots/rover.xml:
 * wheel radius 0.045 m, wheels at y = +-0.11 m, so a track of 0.22 m.
 * Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include <hal/hal.h>
#include <math.h>
#include <stdio.h>

#define PI_F 3.14159265f
#define CONSOLE 0
#define LEFT_A 64
#define LEFT_B 65
#define RIGHT_A 66
#define RIGHT_B 67

/* Motor Shield R3: channel A drives the left motor, channel B the right one. */
#define LEFT_PWM 3
#define LEFT_DIR 12
#define LEFT_BRAKE 9
#define RIGHT_PWM 11
#define RIGHT_DIR 13
#define RIGHT_BRAKE 8

#define COUNTS_PER_REV 360
#define WHEEL_RADIUS_M 0.045f
#define TRACK_M 0.22f
#define M_PER_COUNT (2.0f * PI_F * WHEEL_RADIUS_M / (float)COUNTS_PER_REV) /* 0.785 mm */

#define SIDE_M 1.0f
#define CRUISE 140
#define TURN 100
#define K_HEADING 2.0f    /* steer per radian off the side's heading */
#define TURN_LEAD_RAD 0.05f /* stop turning a little early: the rover coasts on */
#define STEP_MS 20

/* Gray-code step from the previous (A<<1 | B) state to the new one, index prev * 4 + now:
 * +1 for 00 -> 10 -> 11 -> 01 -> 00 (A leading: forward), -1 backwards, 0 for no change, and
 * 0 for both channels changing at once, an edge missed, counted in *_errors. */
static const int8_t quadrature_step[16] = {0, -1, 1, 0, 1, 0, 0, -1, -1, 0, 0, 1, 0, 1, -1, 0};

struct encoder {
  volatile int32_t count;
  volatile uint16_t errors;
  volatile uint8_t state;
  uint8_t pin_a, pin_b;
};

static struct encoder left = {0, 0, 0, LEFT_A, LEFT_B};
static struct encoder right = {0, 0, 0, RIGHT_A, RIGHT_B};

static uint8_t encoder_state(const struct encoder *e) {
  return (uint8_t)((digital_read(e->pin_a) << 1) | digital_read(e->pin_b));
}

static void encoder_edge(struct encoder *e) {
  const uint8_t now = encoder_state(e);
  const uint8_t index = (uint8_t)((e->state << 2) | now);
  if (now != e->state && quadrature_step[index] == 0) e->errors++;
  e->count += quadrature_step[index];
  e->state = now;
}

static void on_left(void) { encoder_edge(&left); }
static void on_right(void) { encoder_edge(&right); }

static int32_t read_count(struct encoder *e) {
  irq_disable(); /* four byte reads on the AVR: keep the handler out */
  const int32_t count = e->count;
  irq_enable();
  return count;
}

struct pose {
  float x, y, theta; /* metres from the start, x along the start heading; radians, anticlockwise */
};

/* One odometry step for the distances each wheel rolled: the midpoint rule, exact for arcs up
 * to the second order in the heading change. */
static void integrate(struct pose *p, float left_m, float right_m) {
  const float ds = 0.5f * (left_m + right_m);
  const float dtheta = (right_m - left_m) / TRACK_M;
  const float mid = p->theta + 0.5f * dtheta;
  p->x += ds * cosf(mid);
  p->y += ds * sinf(mid);
  p->theta += dtheta;
}

static void motor(uint8_t pwm_pin, uint8_t dir_pin, uint8_t brake_pin, int16_t speed) {
  digital_write(brake_pin, LOW);
  digital_write(dir_pin, speed >= 0 ? HIGH : LOW);
  pwm_write(pwm_pin, (uint8_t)(speed >= 0 ? speed : -speed));
}

static void drive(int16_t l, int16_t r) {
  motor(LEFT_PWM, LEFT_DIR, LEFT_BRAKE, l);
  motor(RIGHT_PWM, RIGHT_DIR, RIGHT_BRAKE, r);
}

static void brake(void) {
  pwm_write(LEFT_PWM, 0);
  pwm_write(RIGHT_PWM, 0);
  digital_write(LEFT_BRAKE, HIGH);
  digital_write(RIGHT_BRAKE, HIGH);
}

/* "-1.23" from a value in units of 1/100 */
static void hundredths(char *out, uint8_t size, float value) {
  const int32_t v = (int32_t)lroundf(value * 100.0f);
  const uint32_t m = (uint32_t)(v < 0 ? -v : v);
  snprintf(out, size, "%s%lu.%02lu", v < 0 ? "-" : "", (unsigned long)(m / 100u), (unsigned long)(m % 100u));
}

enum { STRAIGHT, TURNING, DONE };

int main(void) {
  hal_init();
  uart_begin(CONSOLE, 115200);
  pin_mode(LEFT_DIR, OUTPUT);
  pin_mode(LEFT_BRAKE, OUTPUT);
  pin_mode(RIGHT_DIR, OUTPUT);
  pin_mode(RIGHT_BRAKE, OUTPUT);
  drive(0, 0);
  pin_mode(LEFT_A, INPUT);
  pin_mode(LEFT_B, INPUT);
  pin_mode(RIGHT_A, INPUT);
  pin_mode(RIGHT_B, INPUT);
  left.state = encoder_state(&left);
  right.state = encoder_state(&right);
  irq_attach_pin(LEFT_A, IRQ_CHANGE, on_left);
  irq_attach_pin(LEFT_B, IRQ_CHANGE, on_left);
  irq_attach_pin(RIGHT_A, IRQ_CHANGE, on_right);
  irq_attach_pin(RIGHT_B, IRQ_CHANGE, on_right);
  uart_print(CONSOLE, "dead_reckoning: ready, driving a 1 m square\r\n");

  struct pose pose = {0, 0, 0};
  int32_t last_left = 0, last_right = 0;
  float side_start_x = 0, side_start_y = 0, side_heading = 0;
  uint8_t phase = STRAIGHT, sides = 0;
  uint32_t next_step = millis(), next_report = millis();
  char line[128], x[16], y[16], h[16];
  for (;;) {
    const int32_t l = read_count(&left), r = read_count(&right);
    integrate(&pose, (float)(l - last_left) * M_PER_COUNT, (float)(r - last_right) * M_PER_COUNT);
    last_left = l;
    last_right = r;

    if (phase == STRAIGHT) {
      const float dx = pose.x - side_start_x, dy = pose.y - side_start_y;
      if (dx * dx + dy * dy >= SIDE_M * SIDE_M) {
        phase = TURNING;
        drive(-TURN, TURN);
      } else {
        const float steer = K_HEADING * (side_heading - pose.theta); /* positive: turn left */
        drive((int16_t)((float)CRUISE * (1.0f - steer)), (int16_t)((float)CRUISE * (1.0f + steer)));
      }
    } else if (phase == TURNING && pose.theta >= side_heading + 0.5f * PI_F - TURN_LEAD_RAD) {
      side_heading += 0.5f * PI_F;
      side_start_x = pose.x;
      side_start_y = pose.y;
      if (++sides == 4) {
        phase = DONE;
        brake();
        uart_print(CONSOLE, "square done\r\n");
      } else {
        phase = STRAIGHT;
      }
    }

    const uint32_t now = millis();
    if ((int32_t)(now - next_report) >= 0) {
      next_report += 500;
      hundredths(x, sizeof x, pose.x);
      hundredths(y, sizeof y, pose.y);
      /* heading in tenths of a degree, shown with one decimal */
      const int32_t tenths = (int32_t)lroundf(pose.theta * 1800.0f / PI_F);
      const uint32_t t = (uint32_t)(tenths < 0 ? -tenths : tenths);
      snprintf(h, sizeof h, "%s%lu.%lu", tenths < 0 ? "-" : "", (unsigned long)(t / 10u), (unsigned long)(t % 10u));
      snprintf(line, sizeof line, "x %s m, y %s m, heading %s deg, counts L %ld R %ld, errors %u\r\n", x, y, h,
               (long)l, (long)r, (unsigned)(left.errors + right.errors));
      uart_print(CONSOLE, line);
    }
    next_step += STEP_MS;
    while ((int32_t)(millis() - next_step) < 0) delay_ms(1);
  }
}
