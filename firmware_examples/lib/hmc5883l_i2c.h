/* A Honeywell HMC5883L magnetometer on I2C (0x1E): identified, set to 8-sample averages at 15 Hz,
 * +-1.3 Ga and continuous measurement, and read as raw X, Y, Z counts (1090 per gauss). */
#ifndef FIRMWARE_HMC5883L_I2C_H
#define FIRMWARE_HMC5883L_I2C_H
#include <stdint.h>

#define HMC_OVERFLOW (-4096) /* what an axis reads when the field exceeds the range */

/* 1 when the chip answered with 'H43' and took the settings. */
uint8_t compass_begin(void);
/* The last measurement in the chip's axes; 0 when the bus failed. */
uint8_t compass_read(int16_t *x, int16_t *y, int16_t *z);
/* True heading in radians, clockwise from north (0..2 pi), for a compass mounted level with X
 * ahead and Y to the left; negative when unread or overflowed. */
float compass_heading(float declination_deg);

#endif
