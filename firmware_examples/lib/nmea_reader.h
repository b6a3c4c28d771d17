/* A GPS receiver's NMEA 0183 output read byte by byte: sentences checksummed, RMC and GGA taken
 * apart into a fix. Positions are whole 1e-5 arc minutes in int32_t (1.85 cm of latitude): a float
 * has 24 bits, so 52 degrees in float degrees would be good to only about a metre. */
#ifndef FIRMWARE_NMEA_READER_H
#define FIRMWARE_NMEA_READER_H
#include <stdint.h>

#define NMEA_M_PER_UNIT 0.018532f /* 1e-5 arc minute of a great circle on a 6371 km sphere */

struct fix_point {
  int32_t lat, lon; /* 1e-5 arc minutes, north and east positive */
};

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
  int16_t course_deg; /* RMC course over ground, whole degrees from true north; -1 when not given */
};

/* One received byte; a sentence that ends here and checks out updates *gps. */
void nmea_feed(struct nmea *p, struct gps_state *gps, uint8_t byte);

/* Offset of `to` from `from` in metres east and north (a flat patch of sphere). */
void nmea_offset_m(const struct fix_point *from, const struct fix_point *to, float *east, float *north);

#endif
