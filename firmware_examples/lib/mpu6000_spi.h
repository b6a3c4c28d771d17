/* An InvenSense MPU-6000 on SPI, mode 3, with its own chip-select pin: registers written one at a
 * time at 1 MHz, samples read in one 14-byte burst at the fast clock. */
#ifndef FIRMWARE_MPU6000_SPI_H
#define FIRMWARE_MPU6000_SPI_H
#include <stdint.h>

#define MPU_SLOW_SPI 1000000uL  /* any register */
#define MPU_FAST_SPI 20000000uL /* sensor registers only; the AVR makes 8 MHz of it */

struct mpu_settings {
  uint8_t sample_div; /* SMPLRT_DIV: the gyro rate (1 kHz with the DLPF on) / (1 + this) */
  uint8_t dlpf;       /* CONFIG's DLPF_CFG */
  uint8_t gyro_fs;    /* GYRO_CONFIG: FS_SEL << 3 */
  uint8_t accel_fs;   /* ACCEL_CONFIG: AFS_SEL << 3 */
};

struct mpu_sample {
  int16_t ax, ay, az, temp, gx, gy, gz;
};

/* Chip select to an output, held HIGH. */
void mpu_select_pin(uint8_t cs);
/* Checks WHO_AM_I, wakes the chip onto `clock_source` (PWR_MGMT_1), takes the settings with the
 * data-ready interrupt as a 50 us pulse, reads them back and leaves the SPI at the fast clock.
 * 1 when it all took. */
uint8_t mpu_begin(const struct mpu_settings *s, uint8_t clock_source);
/* The latest sample, in one burst from ACCEL_XOUT_H. */
struct mpu_sample mpu_read_sample(void);

#endif
