/* A byte on a serial line as the UART devices here send and receive it: 8N1 at `baud`, stamped
 * with the end of its stop bit, in integer nanoseconds of simulated time. */
#ifndef SEAR_DEVICES_SERIAL_BYTE_H
#define SEAR_DEVICES_SERIAL_BYTE_H

#include <stdint.h>

struct serial_byte {
  int64_t end_ns; /* end of the stop bit */
  uint32_t baud;  /* the rate it was sent at: a receiver at another rate reads garbage */
  uint8_t value;
  uint8_t reserved[3];
};

/* One 8N1 frame (start, 8 data, stop) lasts 10 bit times; rounded to the nearest nanosecond. */
static inline int64_t serial_frame_ns(uint32_t baud) { return (int64_t)((10000000000ull + baud / 2) / baud); }

#endif
