// A clean-room host driver for the MPU-6000/6050 doing what InvenSense's motion driver (inv_mpu.c,
// MPU-6050 build) does in mpu_read_fifo and mpu_run_self_test, from its documented arithmetic,
// over the model's SPI or I2C side with a simulated clock: what tests hold the model against.
#pragma once

#include <cstdint>
#include <vector>

extern "C" {
#include "devices/mpu6000.h"
}

namespace sear::test {

// Register accesses as a driver makes them, each at the bus's clock; delay_ms moves the clock.
struct MpuBus {
  mpu6000* s;
  bool i2c;
  int64_t now_ns = 0;

  void write(uint8_t reg, const std::vector<uint8_t>& bytes);
  void write1(uint8_t reg, uint8_t v) { write(reg, {v}); }
  std::vector<uint8_t> read(uint8_t reg, size_t n);
  uint8_t read1(uint8_t reg) { return read(reg, 1)[0]; }
  void delay_ms(int ms) { now_ns += static_cast<int64_t>(ms) * 1000000; }
};

// get_st_biases: the mean output over 50 ms of 1 kHz FIFO packets, gyro at +-250 deg/s and accel
// at +-16 g, with or without the self-test bits; q16 deg/s and q16 g, 1 g taken off Z.
struct StBiases {
  long gyro[3];
  long accel[3];
  int packets;
};
StBiases st_biases(MpuBus& bus, bool hw_test);

// mpu_run_self_test's verdict: bit 0 gyro passed, bit 1 accel passed. The responses it measured
// (deg/s, g) and their relative change from the trims it decoded are kept for the test to show.
struct SelfTestResult {
  int result;
  double gyro_response_dps[3], gyro_var[3];
  double accel_response_g[3], accel_var[3];
};
SelfTestResult run_self_test(MpuBus& bus);

// mpu_read_fifo for 12-byte packets (accel then gyro): 0 and one packet, 0 and nothing when
// less than a packet waits, or -2 after it found FIFO_OFLOW_INT set and reset the FIFO.
int read_fifo(MpuBus& bus, int16_t accel[3], int16_t gyro[3]);

}  // namespace sear::test
