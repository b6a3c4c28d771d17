/* NMEA 0183 sentences from a GPS receiver: see nmea_reader.h. Sentences are "$...*hh<CR><LF>", at
 * most 82 characters, hh the XOR of everything between $ and * (NMEA 0183; u-blox 6 Receiver
 * Description, section "NMEA Protocol"); RMC and GGA fields as listed there.
 * Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include "nmea_reader.h"

#include <hal/hal.h>
#include <math.h>
#include <string.h>

#define PI_F 3.14159265f

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

/* The whole part of a field such as RMC's course "123.4"; -1 when empty or malformed. */
static int16_t whole_number(const char *s) {
  int16_t value = 0;
  uint8_t i = 0;
  for (; s[i] >= '0' && s[i] <= '9'; ++i) {
    if (i == 4) return -1;
    value = (int16_t)(value * 10 + (s[i] - '0'));
  }
  return i > 0 && (s[i] == '.' || s[i] == '\0') ? value : -1;
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
    gps->course_deg = n >= 9 ? whole_number(f[8]) : -1;
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

void nmea_feed(struct nmea *p, struct gps_state *gps, uint8_t byte) {
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

void nmea_offset_m(const struct fix_point *from, const struct fix_point *to, float *east, float *north) {
  const float lat_rad = (float)from->lat / 6000000.0f * PI_F / 180.0f;
  *north = (float)(to->lat - from->lat) * NMEA_M_PER_UNIT;
  *east = (float)(to->lon - from->lon) * NMEA_M_PER_UNIT * cosf(lat_rad);
}

