/* Wall follower for the rover with a SICK LMS200 laser scanner on UART1: configures the scanner
 * (baud rate, 180 degree / 0.5 degree variant, continuous output) and frames and checks its
 * telegrams through ../lib/lms2xx_client, and keeps a wall about 0.5 m off the right side, slowing
 * down and turning left for whatever is ahead.
 * Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include <hal/hal.h>
#include <math.h>
#include <stdio.h>

#include "../lib/lms2xx_client.h"
#include "../lib/motor_shield.h"

#define CONSOLE 0
#define LMS 1 /* UART1: TX1 pin 18 to the scanner's RxD, RX1 pin 19 from its TxD */

static void say(const char *text) { uart_print(CONSOLE, text); }

/* Geometry and control, in millimetres (int) or metres and radians (float). */
#define HALF_WIDTH_MM 250 /* the rover is 0.25 m wide over its tyres, plus a margin each side */
#define BESIDE_MM 400     /* points right of the rover and at most this far ahead are beside it */
#define ON_LINE_MM 60     /* a wall's points lie this close to one line: the scan's noise and more */
#define WALL_M 0.5f       /* wanted distance from the wall on the right */
#define WALL_SEEN_MM 2500 /* beyond this the right side counts as open */
#define SLOW_MM 1000      /* start slowing down and turning left for things ahead */
#define STOP_MM 380       /* turn on the spot below this */
#define CRUISE 140        /* PWM duty of 255 */
#define CREEP 80
#define SPIN 120
#define K_DIST 2.0f  /* steer per metre of distance error */
#define K_ANGLE 1.2f /* steer per radian of heading towards the wall */
#define STEER_MAX 0.8f


/* The nearest return among values from..to, as a point in the scanner's frame (x ahead, y left). */
struct point {
  int32_t x, y;
  uint16_t r;
};
static struct point nearest(uint16_t from, uint16_t to, uint8_t unit) {
  struct point p = {0, 0, LMS_NOTHING_MM};
  uint16_t best = from;
  for (uint16_t i = from; i <= to; ++i) {
    const uint16_t r = lms_range_mm(i, unit);
    if (r < p.r) {
      p.r = r;
      best = i;
    }
  }
  /* value i looks i/2 degrees left of the scanner's right, i.e. at (i/2 - 90) degrees */
  p.x = ((int32_t)p.r * lms_sin_k(best)) >> 14;
  p.y = -(((int32_t)p.r * lms_cos_k(best)) >> 14);
  return p;
}

struct view {
  uint16_t ahead_mm; /* nearest thing in the rover's path */
  uint8_t wall;      /* a wall on the right */
  float wall_m;      /* its distance from the scanner's axis, or of anything closer beside it */
  float wall_rad;    /* its direction: positive when the rover heads towards it */
};

static struct view look(uint8_t unit) {
  struct view v;
  v.ahead_mm = LMS_NOTHING_MM;
  uint16_t beside_mm = LMS_NOTHING_MM;
  for (uint16_t i = 0; i < LMS_SCAN_VALUES; ++i) {
    const uint16_t r = lms_range_mm(i, unit);
    if (r >= LMS_NOTHING_MM) continue;
    const int32_t x = ((int32_t)r * lms_sin_k(i)) >> 14;
    const int32_t y = -(((int32_t)r * lms_cos_k(i)) >> 14);
    if (x > 0 && x < v.ahead_mm && y > -HALF_WIDTH_MM && y < HALF_WIDTH_MM) v.ahead_mm = (uint16_t)x;
    if (y < 0 && x < BESIDE_MM && -y < beside_mm) beside_mm = (uint16_t)-y;
  }
  /* Two points on the right wall, one abeam (-90..-88 degrees) and one ahead of it (-52..-48):
   * the line through them gives the wall's distance and direction, if a third point between them
   * (-72..-68) lies on it too. Otherwise they are on different things (a box abeam, the wall
   * behind it ahead), the line means nothing, and whatever is nearest beside the rover is the
   * distance to keep. */
  const struct point abeam = nearest(0, 4, unit);
  const struct point fore = nearest(76, 84, unit);
  const struct point middle = nearest(36, 44, unit);
  v.wall = abeam.r < WALL_SEEN_MM || fore.r < WALL_SEEN_MM || beside_mm < WALL_SEEN_MM;
  v.wall_m = (float)beside_mm / 1000.0f;
  v.wall_rad = 0;
  if (abeam.r < WALL_SEEN_MM && fore.r < WALL_SEEN_MM && middle.r < WALL_SEEN_MM) {
    const float dx = (float)(fore.x - abeam.x), dy = (float)(fore.y - abeam.y);
    const float length = sqrtf(dx * dx + dy * dy);
    const float off_line =
        fabsf((float)(middle.x - abeam.x) * dy - (float)(middle.y - abeam.y) * dx) / (length + 1.0f);
    if (length > 1.0f && off_line < (float)ON_LINE_MM) {
      v.wall_rad = atan2f(dy, dx);
      v.wall_m = fabsf((float)abeam.x * dy - (float)abeam.y * dx) / length / 1000.0f;
    }
  }
  return v;
}

static int16_t clamp_duty(float duty) {
  if (duty > 255.0f) return 255;
  if (duty < -255.0f) return -255;
  return (int16_t)duty;
}

/* steer -1..1, positive to the left */
static void drive(int16_t base, float steer) {
  motors_drive(clamp_duty((float)base * (1.0f - steer)), clamp_duty((float)base * (1.0f + steer)));
}

static void spin_left(void) {
  motors_drive(-SPIN, SPIN);
}

/* The wall follower's rule: a speed and a steer (-1..1, positive left) for what the scan shows;
 * returns 1 to turn left on the spot instead. */
static uint8_t decide(const struct view *v, int16_t *base, float *steer) {
  if (v->ahead_mm < STOP_MM) {
    *base = 0;
    *steer = 1;
    return 1;
  }
  float s = v->wall ? K_ANGLE * v->wall_rad - K_DIST * (v->wall_m - WALL_M)
                    : -0.25f; /* open on the right: arc right until a wall turns up */
  *base = CRUISE;
  if (v->ahead_mm < SLOW_MM) {
    /* closer: slower and further left, so that a corner ahead becomes the next wall */
    const float near = (float)(SLOW_MM - v->ahead_mm) / (float)(SLOW_MM - STOP_MM);
    *base = (int16_t)(CREEP + (float)(CRUISE - CREEP) * (1.0f - near));
    s += near;
  }
  if (s > STEER_MAX) s = STEER_MAX;
  if (s < -STEER_MAX) s = -STEER_MAX;
  *steer = s;
  return 0;
}

/* "1.23" for a distance in millimetres */
static void metres(char *out, uint8_t size, uint16_t mm) {
  snprintf(out, size, "%u.%02u", mm / 1000u, (mm % 1000u) / 10u);
}

int main(void) {
  hal_init();
  uart_begin(CONSOLE, 115200);
  motors_begin();
  drive(0, 0);
  lms_fill_sin_table();
  say("wall_follower: ready\r\n");
  lms_start(LMS);

  uint32_t scans = 0, last_scan_ms = millis(), next_report_ms = millis();
  uint16_t odd_scans = 0;
  float steer = 0;
  struct view v = {LMS_NOTHING_MM, 0, 0, 0};
  char line[96], right[8], ahead[8];
  for (;;) {
    if (lms_poll()) {
      const uint8_t cmd = lms_telegram[4];
      const uint16_t count = (uint16_t)(lms_telegram[5] | ((uint16_t)lms_telegram[6] << 8));
      if (cmd == LMS_CMD_SCAN && (count & 0x3FFu) == LMS_SCAN_VALUES && (count >> 14) <= 1) {
        v = look((uint8_t)(count >> 14));
        scans++;
        last_scan_ms = millis();
      } else if (cmd == LMS_CMD_SCAN) {
        odd_scans++;
      }
      lms_release();

      int16_t base;
      if (decide(&v, &base, &steer)) spin_left();
      else drive(base, steer);
    } else if (millis() - last_scan_ms > 500u) {
      steer = 0;
      drive(0, 0); /* blind: stand still until scans come back */
    }

    if ((int32_t)(millis() - next_report_ms) >= 0) {
      next_report_ms += 500u;
      metres(right, sizeof right, v.wall ? (uint16_t)(v.wall_m * 1000.0f) : LMS_NOTHING_MM);
      metres(ahead, sizeof ahead, v.ahead_mm);
      const int16_t s = (int16_t)lroundf(steer * 100.0f);
      const uint16_t s_abs = (uint16_t)(s < 0 ? -s : s);
      snprintf(line, sizeof line, "scan %lu: right %s m, ahead %s m, steer %c%u.%02u, crc errors %u\r\n",
               (unsigned long)scans, v.wall ? right : "--", ahead, s < 0 ? '-' : '+', s_abs / 100u, s_abs % 100u,
               lms_crc_errors);
      say(line);
      if (odd_scans) {
        snprintf(line, sizeof line, "  %u scans of an unexpected size or unit\r\n", odd_scans);
        say(line);
        odd_scans = 0;
      }
    }
    delay_ms(1);
  }
}
