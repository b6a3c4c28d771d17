#include "mpu6000_driver.hpp"

#include <cmath>
#include <cstdlib>

namespace sear::test {

namespace {

// inv_mpu.c's test parameters for the MPU-6050: sensitivities at the test's full scales, the
// filter and rate, the window, and the pass limits.
constexpr long kGyroSens = 32768 / 250;  // 131 LSB per deg/s at +-250 deg/s
constexpr long kAccelSens = 32768 / 16;  // 2048 LSB per g at +-16 g
constexpr uint8_t kTestLpf = 1;          // 188 Hz
constexpr uint8_t kTestRateDiv = 0;      // 1 kHz
constexpr uint8_t kTestAccelFsr = 0x18;  // +-16 g
constexpr int kWaitMs = 50;
constexpr double kMinDps = 10.0, kMaxDps = 105.0, kMaxGyroVar = 0.14;
constexpr double kMinG = 0.3, kMaxG = 0.95, kMaxAccelVar = 0.14;
constexpr int kPacket = 12;

constexpr uint8_t kI2cMstCtrl = 0x24;
constexpr uint8_t kDmpReset = 0x08;

int16_t be16(const std::vector<uint8_t>& d, size_t i) { return static_cast<int16_t>((d[i] << 8) | d[i + 1]); }

}  // namespace

void MpuBus::write(uint8_t reg, const std::vector<uint8_t>& bytes) {
  if (i2c) {
    std::vector<uint8_t> d{reg};
    d.insert(d.end(), bytes.begin(), bytes.end());
    mpu6000_i2c_write(s, d.data(), d.size(), now_ns);
    return;
  }
  mpu6000_spi_select(s, 1, now_ns);
  mpu6000_spi_transfer(s, reg, 1000000, now_ns);
  for (uint8_t b : bytes) mpu6000_spi_transfer(s, b, 1000000, now_ns);
  mpu6000_spi_select(s, 0, now_ns);
}

std::vector<uint8_t> MpuBus::read(uint8_t reg, size_t n) {
  std::vector<uint8_t> out(n);
  if (i2c) {
    mpu6000_i2c_write(s, &reg, 1, now_ns);
    mpu6000_i2c_read(s, out.data(), n, now_ns);
    return out;
  }
  mpu6000_spi_select(s, 1, now_ns);
  mpu6000_spi_transfer(s, static_cast<uint8_t>(reg | 0x80), 1000000, now_ns);
  for (size_t i = 0; i < n; ++i) out[i] = mpu6000_spi_transfer(s, 0, 1000000, now_ns);
  mpu6000_spi_select(s, 0, now_ns);
  return out;
}

StBiases st_biases(MpuBus& bus, bool hw_test) {
  bus.write(MPU6000_PWR_MGMT_1, {0x01, 0x00});  // PLL with the X gyro, nothing in standby
  bus.delay_ms(200);
  bus.write1(MPU6000_INT_ENABLE, 0);
  bus.write1(MPU6000_FIFO_EN, 0);
  bus.write1(MPU6000_PWR_MGMT_1, 0);
  bus.write1(kI2cMstCtrl, 0);
  bus.write1(MPU6000_USER_CTRL, 0);
  bus.write1(MPU6000_USER_CTRL, MPU6000_USER_FIFO_RESET | kDmpReset);
  bus.delay_ms(15);
  bus.write1(MPU6000_CONFIG, kTestLpf);
  bus.write1(MPU6000_SMPLRT_DIV, kTestRateDiv);
  bus.write1(MPU6000_GYRO_CONFIG, hw_test ? MPU6000_XYZ_ST : 0);
  bus.write1(MPU6000_ACCEL_CONFIG, static_cast<uint8_t>(kTestAccelFsr | (hw_test ? MPU6000_XYZ_ST : 0)));
  if (hw_test) bus.delay_ms(200);
  bus.write1(MPU6000_USER_CTRL, MPU6000_USER_FIFO_EN);
  bus.write1(MPU6000_FIFO_EN, MPU6000_FIFO_EN_XG | MPU6000_FIFO_EN_YG | MPU6000_FIFO_EN_ZG | MPU6000_FIFO_EN_ACCEL);
  bus.delay_ms(kWaitMs);
  bus.write1(MPU6000_FIFO_EN, 0);
  const std::vector<uint8_t> c = bus.read(MPU6000_FIFO_COUNTH, 2);
  const int packets = ((c[0] << 8) | c[1]) / kPacket;
  long long gyro[3] = {0, 0, 0}, accel[3] = {0, 0, 0};
  for (int p = 0; p < packets; ++p) {
    const std::vector<uint8_t> d = bus.read(MPU6000_FIFO_R_W, kPacket);
    for (int i = 0; i < 3; ++i) {
      accel[i] += be16(d, 2 * static_cast<size_t>(i));
      gyro[i] += be16(d, 6 + 2 * static_cast<size_t>(i));
    }
  }
  StBiases b{};
  b.packets = packets;
  if (packets == 0) return b;
  for (int i = 0; i < 3; ++i) {
    b.gyro[i] = static_cast<long>((gyro[i] * 65536) / kGyroSens / packets);
    b.accel[i] = static_cast<long>((accel[i] * 65536) / kAccelSens / packets);
  }
  b.accel[2] += b.accel[2] > 0 ? -65536L : 65536L;  // the part lies flat: take 1 g off Z
  return b;
}

SelfTestResult run_self_test(MpuBus& bus) {
  const StBiases regular = st_biases(bus, false);
  const StBiases st = st_biases(bus, true);
  SelfTestResult r{};
  const std::vector<uint8_t> t = bus.read(MPU6000_SELF_TEST_X, 4);
  int gyro_fail = 0, accel_fail = 0;
  for (int i = 0; i < 3; ++i) {
    const size_t axis = static_cast<size_t>(i);
    // Accel: XA_TEST[4:2] from bits 7:5 of its axis' register, [1:0] from SELF_TEST_A.
    const int shift_bits = 4 - 2 * i;
    const int accel_code = ((t[axis] & 0xE0) >> 3) | ((t[3] >> shift_bits) & 3);
    r.accel_response_g[i] = static_cast<double>(std::labs(regular.accel[i] - st.accel[i])) / 65536.0;
    if (accel_code) {
      const double shift = 0.34 * std::pow(1.034, accel_code - 1);
      r.accel_var[i] = r.accel_response_g[i] / shift - 1.0;
      if (std::fabs(r.accel_var[i]) > kMaxAccelVar) accel_fail |= 1 << i;
    } else if (r.accel_response_g[i] < kMinG || r.accel_response_g[i] > kMaxG) {
      accel_fail |= 1 << i;
    }
    // Gyro: XG_TEST in bits 4:0.
    const int gyro_code = t[axis] & 0x1F;
    r.gyro_response_dps[i] = static_cast<double>(std::labs(regular.gyro[i] - st.gyro[i])) / 65536.0;
    if (gyro_code) {
      const double shift = 3275.0 / kGyroSens * std::pow(1.046, gyro_code - 1);
      r.gyro_var[i] = r.gyro_response_dps[i] / shift - 1.0;
      if (std::fabs(r.gyro_var[i]) > kMaxGyroVar) gyro_fail |= 1 << i;
    } else if (r.gyro_response_dps[i] < kMinDps || r.gyro_response_dps[i] > kMaxDps) {
      gyro_fail |= 1 << i;
    }
  }
  r.result = (gyro_fail ? 0 : 1) | (accel_fail ? 0 : 2);
  return r;
}

int read_fifo(MpuBus& bus, int16_t accel[3], int16_t gyro[3]) {
  const std::vector<uint8_t> c = bus.read(MPU6000_FIFO_COUNTH, 2);
  const int count = (c[0] << 8) | c[1];
  if (count < kPacket) return 0;
  if (count > MPU6000_FIFO_BYTES / 2 && (bus.read1(MPU6000_INT_STATUS) & MPU6000_FIFO_OFLOW)) {
    // mpu_reset_fifo: everything off, reset, back on, DATA_RDY again.
    bus.write1(MPU6000_INT_ENABLE, 0);
    bus.write1(MPU6000_FIFO_EN, 0);
    bus.write1(MPU6000_USER_CTRL, 0);
    bus.write1(MPU6000_USER_CTRL, MPU6000_USER_FIFO_RESET);
    bus.write1(MPU6000_USER_CTRL, MPU6000_USER_FIFO_EN);
    bus.delay_ms(50);
    bus.write1(MPU6000_INT_ENABLE, MPU6000_DATA_RDY);
    bus.write1(MPU6000_FIFO_EN, MPU6000_FIFO_EN_XG | MPU6000_FIFO_EN_YG | MPU6000_FIFO_EN_ZG | MPU6000_FIFO_EN_ACCEL);
    return -2;
  }
  const std::vector<uint8_t> d = bus.read(MPU6000_FIFO_R_W, kPacket);
  for (size_t i = 0; i < 3; ++i) {
    accel[i] = be16(d, 2 * i);
    gyro[i] = be16(d, 6 + 2 * i);
  }
  return 0;
}

}  // namespace sear::test
