/* The I2C master: each call is one transaction with the device at its address, which sees it at
 * the moment of the start condition; an address nobody answers is not acknowledged. Each takes
 * its bus time: start, 9 clocks per byte (8 bits and the acknowledge), stop. */
#include <hal/i2c.h>

#include "mcu.h"

void i2c_begin(uint32_t clock_hz) {
  mcu_enter(SEAR_CALL_i2c_begin);
  if (clock_hz < 10000 || clock_hz > 400000) mcu_fatal("i2c_begin(%lu): the TWI runs at 10..400 kHz", (unsigned long)clock_hz);
  sear_mcu.i2c_clock_hz = clock_hz;
}

static void check(uint8_t address, const char *call) {
  if (!sear_mcu.i2c_clock_hz) mcu_fatal("%s: call i2c_begin() first", call);
  if (address > 127) mcu_fatal("%s(0x%02x): I2C addresses are 7 bits", call, address);
}

/* Start and stop, an address byte and `bytes` data bytes, each with its acknowledge. A missing
 * acknowledge ends the transaction after the address byte. */
static int8_t finish(int64_t now, int answered, unsigned bytes) {
  const unsigned clocks = 2 + 9 * (1 + (answered ? bytes : 0));
  mcu_advance_to(now + (int64_t)(clocks * 1000000000ull / sear_mcu.i2c_clock_hz));
  return answered ? I2C_OK : I2C_NACK;
}

int8_t i2c_write(uint8_t address, const uint8_t *data, uint8_t length) {
  const int64_t now = mcu_enter(SEAR_CALL_i2c_write);
  check(address, "i2c_write");
  return finish(now, mcu_devices_i2c_write(address, data, length, now) == 0, length);
}

int8_t i2c_read(uint8_t address, uint8_t *data, uint8_t length) {
  const int64_t now = mcu_enter(SEAR_CALL_i2c_read);
  check(address, "i2c_read");
  return finish(now, mcu_devices_i2c_read(address, data, length, now) == 0, length);
}

int8_t i2c_write_reg(uint8_t address, uint8_t reg, uint8_t value) {
  const int64_t now = mcu_enter(SEAR_CALL_i2c_write_reg);
  check(address, "i2c_write_reg");
  const uint8_t bytes[2] = {reg, value};
  return finish(now, mcu_devices_i2c_write(address, bytes, 2, now) == 0, 2);
}

/* The register pointer is written, then a repeated start reads from it: two transactions' worth
 * of address bytes on the bus, one stop. */
int8_t i2c_read_regs(uint8_t address, uint8_t first_reg, uint8_t *data, uint8_t length) {
  const int64_t now = mcu_enter(SEAR_CALL_i2c_read_regs);
  check(address, "i2c_read_regs");
  const int answered = mcu_devices_i2c_write(address, &first_reg, 1, now) == 0 &&
                       mcu_devices_i2c_read(address, data, length, now) == 0;
  return finish(now, answered, answered ? 1u + 1u + length : 0u);
}
