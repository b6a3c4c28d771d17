/* GPS waypoint follower for the rover: a u-blox NEO-6M on UART3 (NMEA 0183 at 9600 baud, its
 * default), read and checksummed here; an HMC5883L compass on I2C for the heading; the rover
 * drives through a list of waypoints (latitude, longitude) and stops at the last.
 * NMEA: sentences "$...*hh<CR><LF>", at most 82 characters, hh the XOR of everything between $
 * and * (NMEA 0183; u-blox 6 Receiver Description, section "NMEA Protocol"); RMC and GGA fields
 * as listed there. HMC5883L: Honeywell datasheet, registers 00h-0Ch.
 * Positions are whole 1e-5 arc minutes in int32_t (1.85 cm of latitude): a float has 24 bits, so
 * 52 degrees in float degrees would be good to only about a metre.
 * Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include <hal/hal.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#define PI_F 3.14159265f
#define CONSOLE 0
#define GPS 3 /* TX3 pin 14, RX3 pin 15 */

/* Motor Shield R3: channel A drives the left motor, channel B the right one. */
#define LEFT_PWM 3
#define LEFT_DIR 12
#define LEFT_BRAKE 9
#define RIGHT_PWM 11
#define RIGHT_DIR 13
#define RIGHT_BRAKE 8

/* Magnetic declination where the rover drives, east positive: true = magnetic + declination.
 * It must match the project's <magnetic declination_deg>. */
#define DECLINATION_DEG 1.5f

/* The course: a 5 m square from the start (the project's gps_origin, 52.2053 N, 0.1218 E), in
 * 1e-5 arc minutes. 5 m north is 5 / 1853.2 m per minute = 270 units; 5 m east is 440 units at
 * cos(52.2053 deg) = 0.6127. */
struct fix_point {
  int32_t lat, lon; /* 1e-5 arc minutes, north and east positive */
};
static const struct fix_point waypoints[] = {
    {313231800L, 731240L}, /* 5 m east of the start */
    {313232070L, 731240L}, /* then 5 m north */
    {313232070L, 730800L}, /* then 5 m west */
    {313231800L, 730800L}, /* back to the start */
};
#define WAYPOINTS (sizeof waypoints / sizeof waypoints[0])
#define ARRIVED_M 1.0f /* a NEO-6M's fix wanders by about 2.5 m CEP: closer is luck */
#define M_PER_UNIT 0.018532f /* 1e-5 arc minute of a great circle on a 6371 km sphere */

#define CRUISE 150
#define SPIN 110
#define K_STEER 1.0f /* steer per radian of heading error */
#define SPIN_RAD 1.0f /* turn on the spot beyond this heading error */

/* ---- NMEA ---- */

struct nmea {
  char line[83]; /* 82 characters and the terminator */
  uint8_t length;
  uint8_t receiving; /* after a '$', until the end of the line */
  uint16_t bad_checksums, overlong;
};

struct gps_state {
  uint8_t valid;    /* RMC status A and GGA quality > 0 */
  uint8_t sats;     /* GGA satellites used */
  struct fix_point at;
  uint32_t fixes;   /* position updates */
  uint32_t at_ms;   /* time of the last update */
};

static int8_t hex_value(char c) {
  if (c >= '0' && c <= '9') return (int8_t)(c - '0');
  if (c >= 'A' && c <= 'F') return (int8_t)(c - 'A' + 10);
  if (c >= 'a' && c <= 'f') return (int8_t)(c - 'a' + 10);
  return -1;
}

/* "ddmm.mmmmm" (deg_digits 2) or "dddmm.mmmmm" (3) and a hemisphere letter, in 1e-5 minutes;
 * returns 0 when the field is empty or malformed. */
static uint8_t parse_coord(const char *s, uint8_t deg_digits, char hemisphere, int32_t *out) {
  int32_t degrees = 0, minutes = 0, fraction = 0;
  uint8_t i;
  for (i = 0; i < deg_digits; ++i) {
    if (s[i] < '0' || s[i] > '9') return 0;
    degrees = degrees * 10 + (s[i] - '0');
  }
  for (; i < deg_digits + 2u; ++i) {
    if (s[i] < '0' || s[i] > '9') return 0;
    minutes = minutes * 10 + (s[i] - '0');
  }
  if (s[i] == '.') {
    ++i;
    for (uint8_t f = 0; f < 5; ++f) {
      fraction *= 10;
      if (s[i] >= '0' && s[i] <= '9') fraction += s[i++] - '0';
    }
  }
  if (s[i] != '\0' || minutes >= 60) return 0;
  const int32_t value = (degrees * 60 + minutes) * (int32_t)100000 + fraction;
  if (hemisphere == 'S' || hemisphere == 'W') *out = -value;
  else if (hemisphere == 'N' || hemisphere == 'E') *out = value;
  else return 0;
  return 1;
}

/* A field of up to two digits, such as GGA's satellite count; 0 when empty or malformed. */
static uint8_t small_number(const char *s) {
  uint8_t value = 0;
  for (uint8_t i = 0; s[i]; ++i) {
    if (i == 2 || s[i] < '0' || s[i] > '9') return 0;
    value = (uint8_t)(value * 10u + (uint8_t)(s[i] - '0'));
  }
  return value;
}

/* Splits a checked sentence at its commas; returns the number of fields. */
#define MAX_FIELDS 20
static uint8_t split(char *line, char **fields) {
  uint8_t n = 0;
  fields[n++] = line;
  for (char *c = line; *c && n < MAX_FIELDS; ++c) {
    if (*c == ',') {
      *c = '\0';
      fields[n++] = c + 1;
    }
  }
  return n;
}

static void sentence(struct nmea *p, struct gps_state *gps) {
  /* "$" body "*" hh: the checksum covers the body */
  char *star = strchr(p->line, '*');
  if (!star || star[1] == '\0' || star[2] == '\0' || star[3] != '\0') {
    p->bad_checksums++;
    return;
  }
  uint8_t sum = 0;
  for (const char *c = p->line + 1; c < star; ++c) sum ^= (uint8_t)*c;
  const int8_t hi = hex_value(star[1]), lo = hex_value(star[2]);
  if (hi < 0 || lo < 0 || sum != (uint8_t)((hi << 4) | lo)) {
    p->bad_checksums++;
    return;
  }
  *star = '\0';
  char *f[MAX_FIELDS];
  const uint8_t n = split(p->line + 1, f);
  if (strlen(f[0]) != 5) return; /* a talker (GP, GN, ...) and a three-letter type */
  const char *type = f[0] + 2;
  struct fix_point at;
  if (strcmp(type, "RMC") == 0 && n >= 7) {
    /* 1 time, 2 status A/V, 3-4 latitude, 5-6 longitude, 7 speed kn, 8 course, 9 date */
    if (f[2][0] != 'A') {
      gps->valid = 0;
      return;
    }
    if (parse_coord(f[3], 2, f[4][0], &at.lat) && parse_coord(f[5], 3, f[6][0], &at.lon)) {
      gps->at = at;
      gps->valid = 1;
      gps->fixes++;
      gps->at_ms = millis();
    }
  } else if (strcmp(type, "GGA") == 0 && n >= 8) {
    /* 1 time, 2-3 latitude, 4-5 longitude, 6 quality (0 none), 7 satellites, 8 HDOP, 9 altitude */
    gps->sats = small_number(f[7]);
    if (f[6][0] == '0' || f[6][0] == '\0') {
      gps->valid = 0;
      return;
    }
    if (parse_coord(f[2], 2, f[3][0], &at.lat) && parse_coord(f[4], 3, f[5][0], &at.lon)) {
      gps->at = at;
      gps->valid = 1;
      gps->fixes++;
      gps->at_ms = millis();
    }
  }
}

static void nmea_feed(struct nmea *p, struct gps_state *gps, uint8_t byte) {
  if (byte == '$') { /* a new sentence, even in the middle of a broken one */
    p->line[0] = '$';
    p->length = 1;
    p->receiving = 1;
  } else if (!p->receiving) {
    return;
  } else if (byte == '\r' || byte == '\n') {
    p->line[p->length] = '\0';
    p->receiving = 0;
    sentence(p, gps);
  } else if (p->length < sizeof p->line - 1u) {
    p->line[p->length++] = (char)byte;
  } else {
    p->receiving = 0;
    p->overlong++;
  }
}

/* ---- HMC5883L ---- */

#define HMC 0x1E
#define HMC_CONFIG_A 0x00 /* 0x70: 8 samples averaged, 15 Hz, normal bias */
#define HMC_CONFIG_B 0x01 /* 0x20: +-1.3 Ga, 1090 LSB/Ga */
#define HMC_MODE 0x02     /* 0x00: continuous measurement */
#define HMC_DATA 0x03     /* X, Z, Y: MSB first, in that order */
#define HMC_ID 0x0A       /* "H43" */
#define HMC_OVERFLOW (-4096)

static uint8_t compass_begin(void) {
  uint8_t id[3];
  if (i2c_read_regs(HMC, HMC_ID, id, 3) != I2C_OK || id[0] != 'H' || id[1] != '4' || id[2] != '3') return 0;
  return i2c_write_reg(HMC, HMC_CONFIG_A, 0x70) == I2C_OK && i2c_write_reg(HMC, HMC_CONFIG_B, 0x20) == I2C_OK &&
         i2c_write_reg(HMC, HMC_MODE, 0x00) == I2C_OK;
}

/* True heading in radians, clockwise from north (0..2 pi), or a negative value when unread.
 * Mounted level with its X ahead and Y to the left, so north ahead gives +X and north on the
 * left (heading east) gives +Y: heading = atan2(Y, X). */
static float compass_heading(void) {
  uint8_t d[6];
  if (i2c_read_regs(HMC, HMC_DATA, d, 6) != I2C_OK) return -1;
  const int16_t x = (int16_t)(((uint16_t)d[0] << 8) | d[1]);
  const int16_t y = (int16_t)(((uint16_t)d[4] << 8) | d[5]);
  if (x == HMC_OVERFLOW || y == HMC_OVERFLOW) return -1;
  float heading = atan2f((float)y, (float)x) + DECLINATION_DEG * PI_F / 180.0f;
  while (heading < 0) heading += 2 * PI_F;
  while (heading >= 2 * PI_F) heading -= 2 * PI_F;
  return heading;
}

/* ---- driving ---- */

static void motor(uint8_t pwm_pin, uint8_t dir_pin, uint8_t brake_pin, int16_t speed) {
  digital_write(brake_pin, LOW);
  digital_write(dir_pin, speed >= 0 ? HIGH : LOW);
  pwm_write(pwm_pin, (uint8_t)(speed >= 0 ? speed : -speed));
}

static void drive(int16_t left, int16_t right) {
  motor(LEFT_PWM, LEFT_DIR, LEFT_BRAKE, left);
  motor(RIGHT_PWM, RIGHT_DIR, RIGHT_BRAKE, right);
}

/* Offset of `to` from `from` in metres east and north (a flat patch of sphere). */
static void offset_m(const struct fix_point *from, const struct fix_point *to, float *east, float *north) {
  const float lat_rad = (float)from->lat / 6000000.0f * PI_F / 180.0f;
  *north = (float)(to->lat - from->lat) * M_PER_UNIT;
  *east = (float)(to->lon - from->lon) * M_PER_UNIT * cosf(lat_rad);
}

static int16_t deg_of(float rad) { return (int16_t)lroundf(rad * 180.0f / PI_F); }

int main(void) {
  hal_init();
  uart_begin(CONSOLE, 115200);
  uart_begin(GPS, 9600);
  i2c_begin(400000);
  pin_mode(LEFT_DIR, OUTPUT);
  pin_mode(LEFT_BRAKE, OUTPUT);
  pin_mode(RIGHT_DIR, OUTPUT);
  pin_mode(RIGHT_BRAKE, OUTPUT);
  drive(0, 0);
  uart_print(CONSOLE, "gps_waypoints: ready\r\n");
  while (!compass_begin()) {
    uart_print(CONSOLE, "compass: no HMC5883L at 0x1E, trying again\r\n");
    delay_ms(1000);
  }

  static struct nmea parser; /* static: 90 bytes better counted in .bss than found on the stack */
  struct gps_state gps;
  memset(&gps, 0, sizeof gps);
  uint8_t target = 0;
  uint32_t next_compass = millis(), next_report = millis();
  float heading = -1, distance = 0, bearing = 0, steer = 0;
  char line[96];
  for (;;) {
    int16_t byte;
    while ((byte = uart_read(GPS)) >= 0) nmea_feed(&parser, &gps, (uint8_t)byte);

    const uint32_t now = millis();
    if ((int32_t)(now - next_compass) >= 0) {
      next_compass += 67; /* the HMC5883L's 15 Hz */
      heading = compass_heading();
      const uint8_t fresh = gps.valid && now - gps.at_ms < 2000u;
      if (target >= WAYPOINTS || !fresh || heading < 0) {
        drive(0, 0);
      } else {
        float east, north;
        offset_m(&gps.at, &waypoints[target], &east, &north);
        distance = sqrtf(east * east + north * north);
        bearing = atan2f(east, north); /* clockwise from north */
        if (bearing < 0) bearing += 2 * PI_F;
        if (distance < ARRIVED_M) {
          snprintf(line, sizeof line, "waypoint %u reached\r\n", target + 1u);
          uart_print(CONSOLE, line);
          if (++target == WAYPOINTS) uart_print(CONSOLE, "course done\r\n");
        } else {
          float error = bearing - heading; /* positive: the waypoint is to the right */
          while (error > PI_F) error -= 2 * PI_F;
          while (error < -PI_F) error += 2 * PI_F;
          if (error > SPIN_RAD) {
            steer = -1;
            drive(SPIN, -SPIN);
          } else if (error < -SPIN_RAD) {
            steer = 1;
            drive(-SPIN, SPIN);
          } else {
            steer = -K_STEER * error; /* positive steer turns left */
            drive((int16_t)((float)CRUISE * (1.0f - steer)), (int16_t)((float)CRUISE * (1.0f + steer)));
          }
        }
      }
    }

    if ((int32_t)(now - next_report) >= 0) {
      next_report += 1000;
      if (!gps.valid) {
        snprintf(line, sizeof line, "no fix (%u sats), heading %d deg, %u bad checksums\r\n", gps.sats,
                 heading < 0 ? -1 : deg_of(heading), parser.bad_checksums);
      } else {
        const int16_t s = (int16_t)lroundf(steer * 100.0f);
        const uint16_t s_abs = (uint16_t)(s < 0 ? -s : s);
        snprintf(line, sizeof line,
                 "fix %u sats: waypoint %u/%u at %u.%u m, bearing %d, heading %d deg, steer %c%u.%02u\r\n",
                 gps.sats, target < WAYPOINTS ? target + 1u : (unsigned)WAYPOINTS, (unsigned)WAYPOINTS,
                 (unsigned)distance, (unsigned)(distance * 10.0f) % 10u, deg_of(bearing),
                 heading < 0 ? -1 : deg_of(heading), s < 0 ? '-' : '+', s_abs / 100u, s_abs % 100u);
      }
      uart_print(CONSOLE, line);
    }
    delay_ms(2);
  }
}
