/* Dead reckoning from wheel encoders: a quadrature encoder on each wheel (left A/B on pins 64/65,
 * right on 66/67, i.e. A10..A13, all pin-change interrupts) is decoded on every edge of both
 * channels (../lib/quadrature), and the counts are integrated into a differential-drive pose.
 * The rover drives a 1 m square by that pose alone and prints it on the way.
 * Encoders: 360 counts per wheel turn, a count being one edge of either channel (90 cycles per
 * channel), and A leads B while the wheel turns forward. Geometry from assets/robots/rover.xml:
 * wheel radius 0.045 m, wheels at y = +-0.11 m, so a track of 0.22 m.
 * Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include <hal/hal.h>
#include <math.h>
#include <stdio.h>

#include "../lib/motor_shield.h"
#include "../lib/quadrature.h"

#define PI_F 3.14159265f
#define CONSOLE 0
#define LEFT_A 64
#define LEFT_B 65
#define RIGHT_A 66
#define RIGHT_B 67

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

static struct encoder left = {0, 0, 0, LEFT_A, LEFT_B};
static struct encoder right = {0, 0, 0, RIGHT_A, RIGHT_B};

static void on_left(void) { encoder_edge(&left); }
static void on_right(void) { encoder_edge(&right); }

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
  motors_begin();
  motors_drive(0, 0);
  encoder_begin(&left, on_left);
  encoder_begin(&right, on_right);
  uart_print(CONSOLE, "dead_reckoning: ready, driving a 1 m square\r\n");

  struct pose pose = {0, 0, 0};
  int32_t last_left = 0, last_right = 0;
  float side_start_x = 0, side_start_y = 0, side_heading = 0;
  uint8_t phase = STRAIGHT, sides = 0;
  uint32_t next_step = millis(), next_report = millis();
  char line[128], x[16], y[16], h[16];
  for (;;) {
    const int32_t l = encoder_count(&left), r = encoder_count(&right);
    integrate(&pose, (float)(l - last_left) * M_PER_COUNT, (float)(r - last_right) * M_PER_COUNT);
    last_left = l;
    last_right = r;

    if (phase == STRAIGHT) {
      const float dx = pose.x - side_start_x, dy = pose.y - side_start_y;
      if (dx * dx + dy * dy >= SIDE_M * SIDE_M) {
        phase = TURNING;
        motors_drive(-TURN, TURN);
      } else {
        const float steer = K_HEADING * (side_heading - pose.theta); /* positive: turn left */
        motors_drive((int16_t)((float)CRUISE * (1.0f - steer)), (int16_t)((float)CRUISE * (1.0f + steer)));
      }
    } else if (phase == TURNING && pose.theta >= side_heading + 0.5f * PI_F - TURN_LEAD_RAD) {
      side_heading += 0.5f * PI_F;
      side_start_x = pose.x;
      side_start_y = pose.y;
      if (++sides == 4) {
        phase = DONE;
        motors_brake();
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
