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

/* The outcome of a device's answer to a write: -1 from the models means nobody took the address;
 * any other refusal is of a data byte. */
static int8_t outcome(int answer) { return answer == 0 ? I2C_OK : answer == -1 ? I2C_NACK : I2C_NACK_DATA; }

/* Bus time: a start (or repeated start), `bytes` bytes on the wire (address bytes included), 9
 * clocks each (8 bits and the acknowledge), and a stop unless the master keeps the bus. */
static void charge(int64_t now, unsigned bytes, int stop) {
  const unsigned clocks = 1u + (stop ? 1u : 0u) + 9u * bytes;
  mcu_advance_to(now + (int64_t)(clocks * 1000000000ull / sear_mcu.i2c_clock_hz));
}

/* One transaction of `data` bytes: a missing address acknowledge ends it after the address byte. */
static int8_t finish_as(int64_t now, int8_t result, unsigned data, int stop) {
  charge(now, 1u + (result == I2C_NACK ? 0u : data), stop || result != I2C_OK);
  return result;
}

static int8_t finish(int64_t now, int answered, unsigned bytes) {
  return finish_as(now, answered ? I2C_OK : I2C_NACK, bytes, 1);
}

int8_t i2c_write(uint8_t address, const uint8_t *data, uint8_t length) {
  const int64_t now = mcu_enter(SEAR_CALL_i2c_write);
  check(address, "i2c_write");
  return finish_as(now, outcome(mcu_devices_i2c_write(address, data, length, now)), length, 1);
}

int8_t i2c_write_nostop(uint8_t address, const uint8_t *data, uint8_t length) {
  const int64_t now = mcu_enter(SEAR_CALL_i2c_write_nostop);
  check(address, "i2c_write_nostop");
  return finish_as(now, outcome(mcu_devices_i2c_write(address, data, length, now)), length, 0);
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
  return finish_as(now, outcome(mcu_devices_i2c_write(address, bytes, 2, now)), 2, 1);
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

/* Two transactions joined by a repeated start, then one stop. A refused write ends it there. */
int8_t i2c_write_read(uint8_t address, const uint8_t *out, uint8_t out_length, uint8_t *in, uint8_t in_length) {
  const int64_t now = mcu_enter(SEAR_CALL_i2c_write_read);
  check(address, "i2c_write_read");
  const int8_t wrote = outcome(mcu_devices_i2c_write(address, out, out_length, now));
  if (wrote != I2C_OK) return finish_as(now, wrote, out_length, 1);
  const int8_t read = outcome(mcu_devices_i2c_read(address, in, in_length, now));
  /* The repeated start's clock takes the place of the first transaction's stop. */
  charge(now, 1u + out_length + 1u + (read == I2C_OK ? in_length : 0u), 1);
  return read == I2C_OK ? I2C_OK : I2C_NACK;
}
