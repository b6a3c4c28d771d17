/* The I2C (TWI) master (SDA 20, SCL 21 on a Mega), 7-bit addresses. Every call returns I2C_OK,
 * I2C_NACK when no device acknowledged its address, or I2C_NACK_DATA when the device took its
 * address but refused a data byte (the transaction ends there, with a stop). */
#ifndef SEAR_HAL_I2C_H
#define SEAR_HAL_I2C_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define I2C_OK 0
#define I2C_NACK (-1)      /* the address byte was not acknowledged */
#define I2C_NACK_DATA (-2) /* a data byte written was not acknowledged */

void i2c_begin(uint32_t clock_hz); /* 100000 or 400000 */
int8_t i2c_write(uint8_t address, const uint8_t *data, uint8_t length);
int8_t i2c_read(uint8_t address, uint8_t *data, uint8_t length);
int8_t i2c_write_reg(uint8_t address, uint8_t reg, uint8_t value);
int8_t i2c_read_regs(uint8_t address, uint8_t first_reg, uint8_t *data, uint8_t length);
/* out_length bytes written, then a repeated start (no stop in between, so no other master can
 * take the bus) and in_length bytes read, then a stop. */
int8_t i2c_write_read(uint8_t address, const uint8_t *out, uint8_t out_length, uint8_t *in, uint8_t in_length);
/* A write that ends without a stop: the master keeps the bus, and the next i2c_read or i2c_write
 * (to any address) begins with a repeated start. A failed write releases the bus. */
int8_t i2c_write_nostop(uint8_t address, const uint8_t *data, uint8_t length);

#ifdef __cplusplus
}
#endif
#endif
