/* The HMC5883L over I2C: see hmc5883l_i2c.h. Registers from the Honeywell datasheet, 00h-0Ch. */
#include "hmc5883l_i2c.h"

#include <hal/hal.h>
#include <math.h>

#define PI_F 3.14159265f
#define HMC 0x1E
#define HMC_CONFIG_A 0x00 /* 0x70: 8 samples averaged, 15 Hz, normal bias */
#define HMC_CONFIG_B 0x01 /* 0x20: +-1.3 Ga, 1090 LSB/Ga */
#define HMC_MODE 0x02     /* 0x00: continuous measurement */
#define HMC_DATA 0x03     /* X, Z, Y: MSB first, in that order */
#define HMC_ID 0x0A       /* "H43" */

uint8_t compass_begin(void) {
  uint8_t id[3];
  if (i2c_read_regs(HMC, HMC_ID, id, 3) != I2C_OK || id[0] != 'H' || id[1] != '4' || id[2] != '3') return 0;
  return i2c_write_reg(HMC, HMC_CONFIG_A, 0x70) == I2C_OK && i2c_write_reg(HMC, HMC_CONFIG_B, 0x20) == I2C_OK &&
         i2c_write_reg(HMC, HMC_MODE, 0x00) == I2C_OK;
}

uint8_t compass_read(int16_t *x, int16_t *y, int16_t *z) {
  uint8_t d[6];
  if (i2c_read_regs(HMC, HMC_DATA, d, 6) != I2C_OK) return 0;
  *x = (int16_t)(((uint16_t)d[0] << 8) | d[1]);
  *z = (int16_t)(((uint16_t)d[2] << 8) | d[3]);
  *y = (int16_t)(((uint16_t)d[4] << 8) | d[5]);
  return 1;
}

/* North ahead gives +X and north on the left (heading east) gives +Y: heading = atan2(Y, X). */
float compass_heading(float declination_deg) {
  int16_t x, y, z;
  if (!compass_read(&x, &y, &z)) return -1;
  if (x == HMC_OVERFLOW || y == HMC_OVERFLOW) return -1;
  float heading = atan2f((float)y, (float)x) + declination_deg * PI_F / 180.0f;
  while (heading < 0) heading += 2 * PI_F;
  while (heading >= 2 * PI_F) heading -= 2 * PI_F;
  return heading;
}
