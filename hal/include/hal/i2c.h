/* The I2C (TWI) master (SDA 20, SCL 21 on a Mega), 7-bit addresses. Every call returns 0 on
 * success or I2C_NACK when no device acknowledged. */
#ifndef SEAR_HAL_I2C_H
#define SEAR_HAL_I2C_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define I2C_OK 0
#define I2C_NACK (-1)

void i2c_begin(uint32_t clock_hz); /* 100000 or 400000 */
int8_t i2c_write(uint8_t address, const uint8_t *data, uint8_t length);
int8_t i2c_read(uint8_t address, uint8_t *data, uint8_t length);
int8_t i2c_write_reg(uint8_t address, uint8_t reg, uint8_t value);
int8_t i2c_read_regs(uint8_t address, uint8_t first_reg, uint8_t *data, uint8_t length);

#ifdef __cplusplus
}
#endif
#endif
