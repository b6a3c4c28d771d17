/* The I2C master. No I2C device is wired in SEAR yet, so every address goes unacknowledged after
 * its start condition and address byte have taken their time on the bus. */
#include <hal/i2c.h>

#include "mcu.h"

void i2c_begin(uint32_t clock_hz) {
  mcu_enter(SEAR_CALL_i2c_begin);
  if (clock_hz < 10000 || clock_hz > 400000) mcu_fatal("i2c_begin(%lu): the TWI runs at 10..400 kHz", (unsigned long)clock_hz);
  sear_mcu.i2c_clock_hz = clock_hz;
}

/* Start, 7-bit address and R/W, no acknowledge, stop: about 11 bit times. */
static int8_t address_phase(int64_t now, uint8_t address, const char *call) {
  if (!sear_mcu.i2c_clock_hz) mcu_fatal("%s: call i2c_begin() first", call);
  if (address > 127) mcu_fatal("%s(0x%02x): I2C addresses are 7 bits", call, address);
  mcu_advance_to(now + (int64_t)(11ull * 1000000000ull / sear_mcu.i2c_clock_hz));
  return I2C_NACK;
}

int8_t i2c_write(uint8_t address, const uint8_t *data, uint8_t length) {
  (void)data;
  (void)length;
  return address_phase(mcu_enter(SEAR_CALL_i2c_write), address, "i2c_write");
}

int8_t i2c_read(uint8_t address, uint8_t *data, uint8_t length) {
  (void)data;
  (void)length;
  return address_phase(mcu_enter(SEAR_CALL_i2c_read), address, "i2c_read");
}

int8_t i2c_write_reg(uint8_t address, uint8_t reg, uint8_t value) {
  (void)reg;
  (void)value;
  return address_phase(mcu_enter(SEAR_CALL_i2c_write_reg), address, "i2c_write_reg");
}

int8_t i2c_read_regs(uint8_t address, uint8_t first_reg, uint8_t *data, uint8_t length) {
  (void)first_reg;
  (void)data;
  (void)length;
  return address_phase(mcu_enter(SEAR_CALL_i2c_read_regs), address, "i2c_read_regs");
}
