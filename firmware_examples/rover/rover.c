/* The reference rover, the bundled default project's firmware: one ATmega2560 follows a loop of
 * GPS waypoints and steers round obstacles it sees with a SICK LMS200, with every sensor of the
 * default project wired in (see ../../assets/projects/default.xml and ../../README.md).
 * Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include <hal/hal.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../lib/hcsr04.h"
#include "../lib/hmc5883l_i2c.h"
#include "../lib/lms2xx_client.h"
#include "../lib/motor_shield.h"
#include "../lib/mpu6000_spi.h"
#include "../lib/nmea_reader.h"
#include "../lib/quadrature.h"
#include "../lib/ubx.h"

#define PI_F 3.14159265f
#define DEG (PI_F / 180.0f)
#define CONSOLE 0
#define LMS 1 /* UART1: TX1 pin 18, RX1 pin 19 */
#define GPS 3 /* UART3: TX3 pin 14, RX3 pin 15 */
#define IR_LEFT 0 /* ADC channels of the two GP2D12s, looking 30 degrees left and right */
#define IR_RIGHT 1
#define BUMP_PIN 2 /* switch to ground: INT4 */
#define SONAR_TRIG 24
#define SONAR_ECHO 10
#define IMU_CS 53
#define IMU_INT 63 /* A9: pin change */
#define ENC_LEFT_A 64
#define ENC_LEFT_B 65
#define ENC_RIGHT_A 66
#define ENC_RIGHT_B 67

/* Where the project puts the world: <gps_origin> 52.2053 N 0.1218 E in 1e-5 arc minutes, and
 * <magnetic declination_deg> (true = magnetic + declination). */
#define ORIGIN_LAT 313231800L
#define ORIGIN_LON 730800L
#define ORIGIN_LAT_DEG 52.2053f
#define DECLINATION_DEG 0.9f

/* The course, in metres east and north of the origin: a square inside the arena walls (+-15 m),
 * clear of the crates, trees and rock round the middle. */
static const int8_t course_m[][2] = {{7, 7}, {-7, 7}, {-7, -7}, {7, -7}};
#define WAYPOINTS (sizeof course_m / sizeof course_m[0])
static struct fix_point waypoints[WAYPOINTS];
#define ARRIVED_M 1.5f /* the fix wanders by about 2.5 m CEP; closer than this is luck */

/* Geometry: rover 0.25 m over its tyres, scanner 0.05 m ahead of the chassis centre. */
#define HALF_LANE_MM 230  /* half the width of a lane the rover fits through, with a margin */
#define CLEAR_MM 1500     /* a lane free this far is good enough to take */
#define SLOW_MM 1200      /* slow down for anything closer than this in the lane taken */
#define STOP_MM 380       /* turn on the spot for anything this close ahead */
#define SEE_MM 4000       /* farther counts as open */
#define LANES 13          /* candidate directions -60..60 degrees, 10 apart */
#define LANE_STEP_DEG 10
#define IR_NEAR_M 0.22f   /* the IR rangers' own close-range alarm */
#define SONAR_NEAR_CM 30

#define CRUISE 255 /* PWM duties of 255 */
#define CREEP 130
#define SPIN 150
#define BACK 160
#define K_STEER 1.3f /* steer per radian of the lane's angle */
#define STEER_MAX 0.9f

/* Odometry, from assets/robots/rover.xml: 90 mm wheels, encoders at 360 counts per turn. */
#define M_PER_COUNT (2.0f * PI_F * 0.045f / 360.0f)

/* IMU: SMPLRT_DIV 0 with the DLPF on (DLPF_CFG 3, 44 Hz): 1000 samples/s; +-500 deg/s
 * (65.5 LSB per deg/s) and +-4 g. */
static const struct mpu_settings imu_settings = {0, 0x03, 0x08, 0x08};
#define GYRO_LSB_PER_DPS 65.5f
#define CLOCK_PLL_X 0x01 /* PWR_MGMT_1: the X gyro's PLL, steadier than the internal oscillator */

static void say(const char *text) { uart_print(CONSOLE, text); }

/* ---- interrupts ---- */

/* Each data-ready pulse's sample is read at once and summed; the main loop takes the sums.
 * The read (15 SPI bytes and the pin calls around them) takes about 100 us on the ATmega2560,
 * five bytes of the scanner's 500 kbaud stream, which its USART holds only three of: so other
 * interrupts are let in meanwhile, the scanner's receive handler above all. Nothing else uses
 * the SPI bus or the sums, and the next data-ready pulse is a millisecond away; the pulse's own
 * falling edge may come in the middle, and returns at once. */
static volatile int32_t imu_sum_gz, imu_sum_ax, imu_sum_ay, imu_sum_az;
static volatile uint16_t imu_samples;

static void on_imu(void) {
  if (!digital_read(IMU_INT)) return; /* the pulse's falling edge */
  irq_enable();
  const struct mpu_sample s = mpu_read_sample();
  irq_disable();
  imu_sum_gz += s.gz;
  imu_sum_ax += s.ax;
  imu_sum_ay += s.ay;
  imu_sum_az += s.az;
  imu_samples++;
}

struct imu_mean {
  float gz, ax, ay, az; /* raw counts */
  uint16_t n;
};

static struct imu_mean take_imu(void) {
  irq_disable();
  const int32_t gz = imu_sum_gz, ax = imu_sum_ax, ay = imu_sum_ay, az = imu_sum_az;
  const uint16_t n = imu_samples;
  imu_sum_gz = imu_sum_ax = imu_sum_ay = imu_sum_az = 0;
  imu_samples = 0;
  irq_enable();
  struct imu_mean m = {0, 0, 0, 0, n};
  if (n) {
    m.gz = (float)gz / (float)n;
    m.ax = (float)ax / (float)n;
    m.ay = (float)ay / (float)n;
    m.az = (float)az / (float)n;
  }
  return m;
}

static struct encoder enc_left = {0, 0, 0, ENC_LEFT_A, ENC_LEFT_B};
static struct encoder enc_right = {0, 0, 0, ENC_RIGHT_A, ENC_RIGHT_B};
static void on_enc_left(void) { encoder_edge(&enc_left); }
static void on_enc_right(void) { encoder_edge(&enc_right); }

static volatile uint8_t bumped;
static void on_bump(void) { bumped = 1; }

/* ---- GPS ---- */

static struct nmea nmea;
static struct gps_state gps;

static void gps_bytes(void) {
  int16_t byte;
  while ((byte = uart_read(GPS)) >= 0) {
    nmea_feed(&nmea, &gps, (uint8_t)byte);
    ubx_feed((uint8_t)byte);
  }
}

/* Sends a UBX CFG message and waits for its ACK-ACK, trying three times. */
static uint8_t gps_configure(uint8_t id, const uint8_t *payload, uint16_t length) {
  for (uint8_t attempt = 0; attempt < 3; ++attempt) {
    ubx_send(GPS, 0x06, id, payload, length);
    for (uint16_t waited = 0; waited < 1000u; waited += 10u) {
      delay_ms(10);
      gps_bytes();
      const uint8_t ack = ubx_ack(0x06, id);
      if (ack == UBX_ACK_ACK) return 1;
      if (ack == UBX_ACK_NAK) break;
    }
  }
  return 0;
}

/* 5 fixes a second and only RMC and GGA: at 9600 baud the six default sentences would not fit in
 * 200 ms, and RMC and GGA alone are about 150 bytes a fix, 78% of the line. */
static void gps_start(void) {
  static const uint8_t quiet[] = {0x01, 0x02, 0x03, 0x05}; /* GLL, GSA, GSV, VTG */
  uint8_t ok = 1;
  for (uint8_t i = 0; i < sizeof quiet; ++i) {
    const uint8_t msg[3] = {0xF0, quiet[i], 0}; /* CFG-MSG: NMEA class F0, rate 0 on this port */
    ok = (uint8_t)(gps_configure(0x01, msg, 3) && ok);
  }
  const uint8_t rate[6] = {200, 0, 1, 0, 1, 0}; /* CFG-RATE: 200 ms, navRate 1, GPS time */
  ok = (uint8_t)(gps_configure(0x08, rate, 6) && ok);
  say(ok ? "gps: RMC and GGA only, 5 Hz\r\n" : "gps: configuration not acknowledged\r\n");
}

/* Waypoint offsets to latitude and longitude, on a sphere as nmea_offset_m() does it. */
static void plan_course(void) {
  const float east_m_per_unit = NMEA_M_PER_UNIT * cosf(ORIGIN_LAT_DEG * DEG);
  for (uint8_t i = 0; i < WAYPOINTS; ++i) {
    waypoints[i].lat = (int32_t)(ORIGIN_LAT + lroundf((float)course_m[i][1] / NMEA_M_PER_UNIT));
    waypoints[i].lon = (int32_t)(ORIGIN_LON + lroundf((float)course_m[i][0] / east_m_per_unit));
  }
}

/* ---- heading ---- */

static float wrap_pi(float a) {
  while (a > PI_F) a -= 2 * PI_F;
  while (a < -PI_F) a += 2 * PI_F;
  return a;
}

/* True heading from the compass, clockwise from north, with the tilt taken out: on a slope the
 * field's vertical part would leak into X and Y (at 66 degrees of inclination, a 5 degree tilt is
 * a 10 degree error). The accelerometer's mean gives "up" in the chassis frame; forward and left
 * are projected onto the level plane and the field measured against them. Negative when unread. */
static float tilted_heading(const struct imu_mean *m) {
  int16_t x, y, z;
  if (!compass_read(&x, &y, &z) || x == HMC_OVERFLOW || y == HMC_OVERFLOW || z == HMC_OVERFLOW) return -1;
  float ux = m->ax, uy = m->ay, uz = m->az;
  const float norm = sqrtf(ux * ux + uy * uy + uz * uz);
  if (m->n == 0 || norm < 1.0f) {
    ux = 0;
    uy = 0;
    uz = 1;
  } else {
    ux /= norm;
    uy /= norm;
    uz /= norm;
  }
  /* forward, levelled: f - (f.u) u; left, levelled: u x forward */
  const float fx = 1.0f - ux * ux, fy = -ux * uy, fz = -ux * uz;
  const float lx = uy * fz - uz * fy, ly = uz * fx - ux * fz, lz = ux * fy - uy * fx;
  const float north_ahead = (float)x * fx + (float)y * fy + (float)z * fz;
  const float north_left = (float)x * lx + (float)y * ly + (float)z * lz;
  float h = atan2f(north_left, north_ahead) + DECLINATION_DEG * DEG;
  if (h < 0) h += 2 * PI_F;
  return h;
}

/* ---- LIDAR ---- */

/* For each candidate direction (-60..60 degrees, left positive), how far ahead the lane of the
 * rover's width is free, in millimetres from the scanner. */
static uint16_t lane_free[LANES];
static int16_t lane_dx[LANES], lane_dy[LANES]; /* unit directions, scaled by 2^14 */
static uint16_t sector_mm = LMS_NOTHING_MM;     /* nearest return within +-30 degrees */
static uint32_t room_left, room_right;          /* summed clipped ranges on each side */

static void plan_lanes(void) {
  for (uint8_t c = 0; c < LANES; ++c) {
    /* value k looks k/2 - 90 degrees left of ahead */
    const uint16_t k = (uint16_t)(180 + 2 * ((int16_t)c - LANES / 2) * LANE_STEP_DEG);
    lane_dx[c] = lms_sin_k(k);
    lane_dy[c] = (int16_t)-lms_cos_k(k);
  }
}

static void look(uint8_t unit) {
  for (uint8_t c = 0; c < LANES; ++c) lane_free[c] = SEE_MM;
  sector_mm = LMS_NOTHING_MM;
  room_left = room_right = 0;
  for (uint16_t i = 0; i < LMS_SCAN_VALUES; ++i) {
    const uint16_t r = lms_range_mm(i, unit);
    const uint16_t clipped = r > SEE_MM ? SEE_MM : r;
    if (i < 180) room_right += clipped;
    else if (i > 180) room_left += clipped;
    if (i >= 120 && i <= 240 && r < sector_mm) sector_mm = r;
    /* Lanes from every other value (1 degree apart, 8 cm at 4.6 m: no gap the rover fits
     * through): 13 lanes of 32-bit products are the heaviest work on the AVR. */
    if ((i & 1u) || r >= SEE_MM + HALF_LANE_MM) continue;
    const int32_t x = ((int32_t)r * lms_sin_k(i)) >> 14;
    const int32_t y = -(((int32_t)r * lms_cos_k(i)) >> 14);
    for (uint8_t c = 0; c < LANES; ++c) {
      const int32_t along = (x * lane_dx[c] + y * lane_dy[c]) >> 14;
      const int32_t across = (x * lane_dy[c] - y * lane_dx[c]) >> 14;
      if (along > 0 && along < lane_free[c] && across > -HALF_LANE_MM && across < HALF_LANE_MM)
        lane_free[c] = (uint16_t)along;
    }
  }
}

static float lane_rad(uint8_t c) { return (float)(((int16_t)c - LANES / 2) * LANE_STEP_DEG) * DEG; }

/* The lane to take towards `goal` (radians, left positive): the one nearest the goal among
 * those free for CLEAR_MM or up to the waypoint, with a small premium on keeping to the side
 * chosen before so that two equal gaps do not make it dither; the freest lane when none is. */
static uint8_t choose_lane(float goal, uint16_t goal_mm, int8_t *side) {
  uint8_t best = LANES, widest = LANES / 2;
  float best_cost = 1e9f;
  for (uint8_t c = 0; c < LANES; ++c) {
    if (lane_free[c] > lane_free[widest]) widest = c;
    if (lane_free[c] < CLEAR_MM && lane_free[c] < goal_mm) continue;
    const float a = lane_rad(c);
    float cost = fabsf(a - goal);
    if (*side && (a > 0.01f ? 1 : (a < -0.01f ? -1 : 0)) == -*side) cost += 15.0f * DEG;
    if (cost < best_cost) {
      best_cost = cost;
      best = c;
    }
  }
  if (best == LANES) best = widest;
  const float a = lane_rad(best);
  *side = (int8_t)(a > 0.01f ? 1 : (a < -0.01f ? -1 : *side));
  return best;
}

/* ---- close range ---- */

/* A GP2D12's distance from its voltage, a fit through the datasheet's curve (2.4 V at 10 cm,
 * 0.4 V at 80 cm): d = 0.2286 m V / (V - 0.114 V). Beyond 80 cm the curve is useless. */
static float ir_m(uint8_t channel) {
  const float volts = (float)adc_read(channel) * (5.0f / 1024.0f);
  return volts < 0.4f ? 0.8f : 0.2286f / (volts - 0.114f);
}

/* ---- printing ---- */

/* "12.3" for a non-negative value */
static void one_decimal(char *out, uint8_t size, float value) {
  const uint32_t tenths = (uint32_t)lroundf(value < 0 ? 0 : value * 10.0f);
  snprintf(out, size, "%lu.%lu", (unsigned long)(tenths / 10u), (unsigned long)(tenths % 10u));
}

static int16_t deg_of(float rad) { return (int16_t)lroundf(rad / DEG); }

/* ---- main ---- */

enum { WAITING, DRIVING, BACKING, ESCAPING };

int main(void) {
  hal_init();
  uart_begin(CONSOLE, 115200);
  motors_begin();
  motors_drive(0, 0);
  say("rover: ready\r\n");
  lms_fill_sin_table();
  plan_lanes();
  plan_course();

  pin_mode(BUMP_PIN, INPUT_PULLUP);
  irq_attach_pin(BUMP_PIN, IRQ_FALLING, on_bump);
  hcsr04_begin(SONAR_TRIG, SONAR_ECHO);
  encoder_begin(&enc_left, on_enc_left);
  encoder_begin(&enc_right, on_enc_right);

  i2c_begin(400000);
  if (!compass_begin()) say("compass: no HMC5883L at 0x1E\r\n");
  mpu_select_pin(IMU_CS);
  pin_mode(IMU_INT, INPUT);
  delay_ms(100); /* the gyro's start-up time */
  if (mpu_begin(&imu_settings, CLOCK_PLL_X)) irq_attach_pin(IMU_INT, IRQ_CHANGE, on_imu);
  else say("imu: no MPU-6000, or its settings did not take\r\n");

  /* The scanner takes seconds to come up and be configured; the rover stands still all the
   * while, so the IMU's sums meanwhile give the gyro's zero-rate offset. */
  take_imu();
  lms_start(LMS);
  uart_begin(GPS, 9600);
  gps_start();
  const struct imu_mean still = take_imu();
  const float gyro_bias = still.gz;
  char line[128], a[12], b[12], c[12];
  one_decimal(a, sizeof a, fabsf(gyro_bias) / GYRO_LSB_PER_DPS);
  snprintf(line, sizeof line, "imu: %u samples standing, gyro z bias %s%s deg/s\r\n", still.n,
           gyro_bias < 0 ? "-" : "", a);
  say(line);

  uint8_t state = WAITING, target = 0, scans = 0;
  int8_t side = 0;
  float heading = 0, steer = 0, distance = 0, odo = 0;
  uint8_t heading_known = 0;
  uint32_t now = millis(), next_control = now, next_compass = now, next_report = now, next_ping = now;
  uint32_t last_scan = now, state_since = now;
  int32_t last_l = 0, last_r = 0;
  uint16_t sonar_cm = 999;
  uint8_t bumps = 0;
  for (;;) {
    gps_bytes();
    while (lms_poll()) {
      const int8_t unit = lms_scan_unit();
      if (unit >= 0) {
        /* one scan in four, 9 a second: a rover at walking pace moves 8 cm in between */
        if ((++scans & 3u) == 0) look((uint8_t)unit);
        last_scan = millis();
      }
      lms_release();
    }
    now = millis();

    if ((int32_t)(now - next_ping) >= 0) {
      /* the last ping's echo, or "nothing" when it is still high (or never came) a cycle later */
      uint32_t width = 0;
      const uint8_t echoed = hcsr04_done(&width) && width > 0 && width < HCSR04_NO_ECHO_US;
      sonar_cm = echoed ? (uint16_t)(width / HCSR04_US_PER_CM) : 999;
      hcsr04_trigger();
      next_ping = now + HCSR04_CYCLE_MS;
    }

    if ((int32_t)(now - next_control) >= 0) {
      next_control += 20u;
      const struct imu_mean m = take_imu();
      /* gyro z is anticlockwise, the heading clockwise */
      if (heading_known && m.n) heading -= (m.gz - gyro_bias) / GYRO_LSB_PER_DPS * DEG * 0.02f;
      if ((int32_t)(now - next_compass) >= 0) {
        next_compass += 67u; /* the HMC5883L's 15 Hz */
        const float h = tilted_heading(&m);
        if (h >= 0) heading = heading_known ? heading + 0.15f * wrap_pi(h - heading) : h;
        heading_known = (uint8_t)(heading_known || h >= 0);
      }
      if (heading >= 2 * PI_F) heading -= 2 * PI_F;
      if (heading < 0) heading += 2 * PI_F;

      const int32_t l = encoder_count(&enc_left), r = encoder_count(&enc_right);
      odo += 0.5f * (fabsf((float)(l - last_l)) + fabsf((float)(r - last_r))) * M_PER_COUNT;
      last_l = l;
      last_r = r;

      const uint8_t fresh = gps.valid && now - gps.at_ms < 1000u;
      float goal = 0;
      if (fresh && target < WAYPOINTS) {
        float east, north;
        nmea_offset_m(&gps.at, &waypoints[target], &east, &north);
        distance = sqrtf(east * east + north * north);
        if (distance < ARRIVED_M) {
          one_decimal(a, sizeof a, odo);
          snprintf(line, sizeof line, "waypoint %u/%u reached at %lu.%lu s, odo %s m\r\n", target + 1u,
                   (unsigned)WAYPOINTS, (unsigned long)(now / 1000u), (unsigned long)(now / 100u % 10u), a);
          say(line);
          target = (uint8_t)((target + 1u) % WAYPOINTS); /* a loop: round again */
          nmea_offset_m(&gps.at, &waypoints[target], &east, &north);
          distance = sqrtf(east * east + north * north);
        }
        /* bearing clockwise from north; the goal anticlockwise from ahead */
        goal = -wrap_pi(atan2f(east, north) - heading);
      }

      if (bumped) {
        bumped = 0;
        if (state != BACKING) {
          if (bumps++ < 5) say("bump: backing off\r\n");
          state = BACKING;
          state_since = now;
        }
      }
      if (state == WAITING && fresh && heading_known && now - last_scan < 500u) state = DRIVING;

      int16_t left = 0, right = 0;
      if (state == BACKING) {
        left = right = -BACK;
        if (now - state_since > 700u) {
          state = ESCAPING;
          state_since = now;
        }
      } else if (state == ESCAPING) {
        /* turn towards the side with more room */
        const int16_t spin = room_left > room_right ? SPIN : -SPIN;
        left = (int16_t)-spin;
        right = spin;
        if (now - state_since > 600u) state = DRIVING;
      } else if (state == DRIVING) {
        if (!fresh || now - last_scan > 500u) {
          steer = 0; /* blind or lost: stand until the fix and scans come back */
        } else if (fabsf(goal) > 100.0f * DEG) {
          steer = goal > 0 ? 1.0f : -1.0f; /* the waypoint is behind: turn on the spot */
          left = (int16_t)(-SPIN * steer);
          right = (int16_t)(SPIN * steer);
        } else {
          const uint8_t lane = choose_lane(goal, (uint16_t)(distance * 1000.0f), &side);
          const uint16_t free_mm = lane_free[lane];
          const uint8_t blocked =
              lane_free[LANES / 2] < STOP_MM || sonar_cm < SONAR_NEAR_CM || free_mm < STOP_MM;
          steer = K_STEER * lane_rad(lane);
          /* the IR rangers see what is low and close beside the lane */
          const float ir_l = ir_m(IR_LEFT), ir_r = ir_m(IR_RIGHT);
          if (ir_l < IR_NEAR_M) steer -= 0.5f;
          if (ir_r < IR_NEAR_M) steer += 0.5f;
          if (steer > STEER_MAX) steer = STEER_MAX;
          if (steer < -STEER_MAX) steer = -STEER_MAX;
          if (blocked) {
            const int16_t spin = side > 0 || (side == 0 && room_left > room_right) ? SPIN : -SPIN;
            left = (int16_t)-spin;
            right = spin;
          } else {
            const int16_t base = free_mm < SLOW_MM ? CREEP : CRUISE;
            left = (int16_t)((float)base * (1.0f - steer));
            right = (int16_t)((float)base * (1.0f + steer));
            if (left > 255) left = 255;
            if (right > 255) right = 255;
          }
        }
      }
      motors_drive(left, right);
    }

    if ((int32_t)(now - next_report) >= 0) {
      next_report += 1000u;
      one_decimal(a, sizeof a, distance);
      one_decimal(b, sizeof b, odo);
      const uint16_t ahead = sector_mm >= LMS_NOTHING_MM ? 0 : sector_mm;
      snprintf(c, sizeof c, "%u.%02u", ahead / 1000u, ahead % 1000u / 10u);
      snprintf(line, sizeof line, "wp %u/%u at %s m, %s %u sats, heading %d (gps %d), lidar ahead %s m, odo %s m\r\n",
               target + 1u, (unsigned)WAYPOINTS, gps.valid ? a : "--", gps.valid ? "fix" : "no fix", gps.sats,
               heading_known ? deg_of(heading) : -1, gps.valid ? gps.course_deg : -1,
               sector_mm >= LMS_NOTHING_MM ? "--" : c, b);
      say(line);
    }
    delay_ms(2);
  }
}
