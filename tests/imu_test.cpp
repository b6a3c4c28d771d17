// MPU-6000/6050, HMC5883L and QMC5883L models against their datasheets, and the physical truth
// fed to them (specific force with lever arm, the WMM2025 field) against physics and NOAA's model.
#include <ode/ode.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

extern "C" {
#include "devices/hmc5883l.h"
#include "devices/mpu6000.h"
#include "devices/qmc5883l.h"
}
#include "sensors/imu_truth.hpp"
#include "sensors/magnetic_field.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kG = 9.80665;  // the datasheets' g
constexpr int64_t kMs = 1000000;

// ---------- MPU-6000 bus helpers ----------

mpu6000_config clean_config(mpu6000_variant v = MPU6000_VARIANT_6000) {
  mpu6000_config c;
  mpu6000_default_config(&c, v);
  c.gyro = imu_error_figures{};
  c.accel = imu_error_figures{};
  return c;
}

// A register access the way a driver does it over SPI (or I2C for the 6050), at time t.
struct Bus {
  mpu6000* s;
  bool i2c;
  void write(uint8_t reg, uint8_t v, int64_t t, uint32_t sck = 1000000) {
    if (i2c) {
      const uint8_t d[2] = {reg, v};
      ASSERT_EQ(mpu6000_i2c_write(s, d, 2, t), 0);
      return;
    }
    mpu6000_spi_select(s, 1, t);
    mpu6000_spi_transfer(s, reg, sck, t);
    mpu6000_spi_transfer(s, v, sck, t);
    mpu6000_spi_select(s, 0, t);
  }
  std::vector<uint8_t> read(uint8_t reg, size_t n, int64_t t, uint32_t sck = 1000000, int64_t byte_ns = 0) {
    std::vector<uint8_t> out(n);
    if (i2c) {
      EXPECT_EQ(mpu6000_i2c_write(s, &reg, 1, t), 0);
      EXPECT_EQ(mpu6000_i2c_read(s, out.data(), n, t), 0);
      return out;
    }
    mpu6000_spi_select(s, 1, t);
    mpu6000_spi_transfer(s, static_cast<uint8_t>(reg | 0x80), sck, t);
    for (size_t i = 0; i < n; ++i) out[i] = mpu6000_spi_transfer(s, 0, sck, t + static_cast<int64_t>(i + 1) * byte_ns);
    mpu6000_spi_select(s, 0, t + static_cast<int64_t>(n + 1) * byte_ns);
    return out;
  }
  uint8_t read1(uint8_t reg, int64_t t, uint32_t sck = 1000000) { return read(reg, 1, t, sck)[0]; }
};

int16_t be16(const std::vector<uint8_t>& d, size_t i) { return static_cast<int16_t>((d[i] << 8) | d[i + 1]); }

void hold_truth(mpu6000* s, int64_t t, Eigen::Vector3d f, Eigen::Vector3d w) {
  mpu6000_set_truth(s, t, f.data(), w.data());
}

// A noise-free part on SPI, woken at 0 (it powers up asleep): where most register tests start.
Bus woken_on_spi(mpu6000* s) {
  const mpu6000_config c = clean_config();
  mpu6000_init(s, &c, 0);
  Bus bus{s, false};
  bus.write(MPU6000_PWR_MGMT_1, 0, 0);
  return bus;
}

// A part woken with DLPF_CFG `dlpf` and held still, 1 g up, for the error statistics.
void start_at_rest(mpu6000* s, const mpu6000_config& c, uint8_t dlpf) {
  mpu6000_init(s, &c, 0);
  mpu6000_reg_write(s, MPU6000_PWR_MGMT_1, 0);
  mpu6000_reg_write(s, MPU6000_CONFIG, dlpf);
  hold_truth(s, 0, {0, 0, kG}, {0, 0, 0});
}

// The big-endian reading at byte `at` of the data registers (0x3B on), straight from the model.
int16_t shown16(const mpu6000& s, size_t at) { return static_cast<int16_t>((s.shown[at] << 8) | s.shown[at + 1]); }

// ---------- MPU-6000: register file ----------

TEST(Mpu6000, ResetValuesAndSleepUntilWoken) {
  mpu6000 s;
  const mpu6000_config c = clean_config();
  mpu6000_init(&s, &c, 0);
  Bus bus{&s, false};
  // RM-MPU-6000A: every register resets to 0 but WHO_AM_I (0x68) and PWR_MGMT_1 (0x40, asleep);
  // PRODUCT_ID holds a production revision D8 (0x58) that Betaflight's detection accepts, and
  // SELF_TEST_X..A (0x0D-0x10) the factory trims: the default codes gyro 14/15/16 and accel
  // 16/17/18 (0b100.00, 0b100.01, 0b100.10) in RM 4.1's layout.
  const uint8_t trims[4] = {0x80 | 14, 0x80 | 15, 0x80 | 16, 0x00 << 4 | 0x01 << 2 | 0x02};
  for (int r = 0; r < 0x80; ++r) {
    const uint8_t v = bus.read1(static_cast<uint8_t>(r), 0);
    const uint8_t want = r == 0x75 ? 0x68 : r == 0x6B ? 0x40 : r == 0x0C ? 0x58 : (r >= 0x0D && r <= 0x10) ? trims[r - 0x0D] : 0;
    EXPECT_EQ(v, want) << "register 0x" << std::hex << r;
  }
  hold_truth(&s, 0, {0, 0, kG}, {0, 0, 0.5});
  mpu6000_advance(&s, 100 * kMs);
  EXPECT_EQ(be16(bus.read(MPU6000_ACCEL_XOUT_H, 14, 100 * kMs), 4), 0) << "asleep: data registers do not update";
  bus.write(MPU6000_PWR_MGMT_1, 0x00, 100 * kMs);
  // Default DLPF off: gyro output 8 kHz, so the first sample is at most 125 us away.
  const std::vector<uint8_t> d = bus.read(MPU6000_ACCEL_XOUT_H, 14, 100 * kMs + 125000);
  EXPECT_EQ(be16(d, 4), 16384);  // +1 g at +-2 g: 16384 LSB/g
  EXPECT_EQ(be16(d, 12), static_cast<int16_t>(std::lround(0.5 / kDeg * 131.0)));
}

class Mpu6000Buses : public ::testing::TestWithParam<bool> {};

TEST_P(Mpu6000Buses, SensitivityPerRangeAndTemperature) {
  const bool i2c = GetParam();
  mpu6000 s;
  mpu6000_config c = clean_config(i2c ? MPU6000_VARIANT_6050 : MPU6000_VARIANT_6000);
  c.i2c_address = 0x69;
  mpu6000_init(&s, &c, 0);
  Bus bus{&s, i2c};
  bus.write(MPU6000_PWR_MGMT_1, 0x00, 0);
  // PS-MPU-6000A tables 6.1/6.2: 131, 65.5, 32.8, 16.4 LSB/(deg/s); 16384 ... 2048 LSB/g.
  const double gyro_lsb[4] = {131.0, 65.5, 32.8, 16.4};
  const double accel_lsb[4] = {16384, 8192, 4096, 2048};
  const double rate_dps[4] = {200, -400, 900, -1900};  // within each range
  const double force_g[4] = {1.5, -3.2, 7.0, -15.0};
  int64_t t = kMs;
  for (int fs = 0; fs < 4; ++fs) {
    bus.write(MPU6000_GYRO_CONFIG, static_cast<uint8_t>(fs << 3), t);
    bus.write(MPU6000_ACCEL_CONFIG, static_cast<uint8_t>(fs << 3), t);
    hold_truth(&s, t, {force_g[fs] * kG, 0.25 * kG, -0.5 * kG}, {0, rate_dps[fs] * kDeg, 0});
    // The 256/260 Hz filters settle to within exp(-0.707 * 2 pi * 256 Hz * 20 ms) = 1e-10.
    t += 20 * kMs;
    const std::vector<uint8_t> d = bus.read(MPU6000_ACCEL_XOUT_H, 14, t);
    // The filter runs in steady state on a constant input, so the code is the rounded product.
    EXPECT_EQ(be16(d, 0), std::lround(force_g[fs] * accel_lsb[fs])) << "AFS_SEL " << fs;
    EXPECT_EQ(be16(d, 2), std::lround(0.25 * accel_lsb[fs]));
    EXPECT_EQ(be16(d, 4), std::lround(-0.5 * accel_lsb[fs]));
    EXPECT_EQ(be16(d, 10), std::lround(rate_dps[fs] * gyro_lsb[fs])) << "FS_SEL " << fs;
    // RM 4.18: deg C = raw / 340 + 36.53, die at 25 C.
    EXPECT_NEAR(be16(d, 6) / 340.0 + 36.53, 25.0, 0.5 / 340.0);
  }
  // Beyond full scale the output saturates rather than wrapping.
  hold_truth(&s, t, {-20 * kG, 0, 0}, {0, 0, 2500 * kDeg});
  t += 20 * kMs;
  const std::vector<uint8_t> d = bus.read(MPU6000_ACCEL_XOUT_H, 14, t);
  EXPECT_EQ(be16(d, 0), -32768);
  EXPECT_EQ(be16(d, 12), 32767);
}

INSTANTIATE_TEST_SUITE_P(SpiAndI2c, Mpu6000Buses, ::testing::Values(false, true));

TEST(Mpu6000, RevisionCReadsAccelerationAtTwiceTheSensitivity) {
  // ArduPilot/PX4: rev C4/C5 parts give 4096 LSB/g at AFS_SEL = 1, where the map says 8192.
  mpu6000 s;
  mpu6000_config c = clean_config();
  c.product_id = MPU6000_REV_C4;
  mpu6000_init(&s, &c, 0);
  Bus bus{&s, false};
  EXPECT_EQ(bus.read1(MPU6000_PRODUCT_ID, 0), 0x54);
  bus.write(MPU6000_PWR_MGMT_1, 0, 0);
  bus.write(MPU6000_ACCEL_CONFIG, 2 << 3, 0);  // the map's 4096 LSB/g
  hold_truth(&s, 0, {0, 0, kG}, {0, 0, 0});
  EXPECT_EQ(be16(bus.read(MPU6000_ACCEL_XOUT_H, 6, 2 * kMs), 4), 8192);
}

TEST(Mpu6000, BurstReadsComeFromOneSamplingInstant) {
  // Two identical parts see the same ramp of truth. One is read in a single instant; the other
  // byte by byte over 560 us, across four 8 kHz samples. The bursts must agree byte for byte,
  // though the ramp moves ~6 LSB per sample.
  mpu6000 a, b;
  Bus ba = woken_on_spi(&a), bb = woken_on_spi(&b);
  auto truth_at = [](int64_t t) {
    const double x = 1e-6 * static_cast<double>(t);  // per microsecond
    return std::pair<Eigen::Vector3d, Eigen::Vector3d>{{0.02 * x, 0, kG}, {0, 0, 0.0005 * x}};
  };
  for (int64_t t = 0; t <= 20 * kMs; t += 125000) {
    const auto [f, w] = truth_at(t);
    hold_truth(&a, t, f, w);
  }
  const int64_t t0 = 20 * kMs + 60000;
  const std::vector<uint8_t> reference = ba.read(MPU6000_ACCEL_XOUT_H, 14, t0, 20000000);
  // Part b: the same truth history, then its slow burst with the truth still ramping.
  for (int64_t t = 0; t <= 20 * kMs; t += 125000) {
    const auto [f, w] = truth_at(t);
    hold_truth(&b, t, f, w);
  }
  mpu6000_spi_select(&b, 1, t0);
  mpu6000_spi_transfer(&b, MPU6000_ACCEL_XOUT_H | 0x80, 1000000, t0);
  std::vector<uint8_t> slow(14);
  for (int i = 0; i < 14; ++i) {
    const int64_t t = t0 + 40000 * (i + 1);
    if ((t - t0) % 125000 < 40000) {
      const auto [f, w] = truth_at(t);
      hold_truth(&b, t, f, w);
    }
    slow[static_cast<size_t>(i)] = mpu6000_spi_transfer(&b, 0, 1000000, t);
  }
  mpu6000_spi_select(&b, 0, t0 + 600000);
  EXPECT_EQ(slow, reference);
  // After CS rises the newer sample shows: the test above could have failed.
  const std::vector<uint8_t> later = bb.read(MPU6000_ACCEL_XOUT_H, 14, t0 + 600000);
  EXPECT_NE(be16(later, 12), be16(reference, 12));
}

// Amplitude of a sinusoid of frequency f in samples x taken every dt (single-bin DFT).
double amplitude_at(const std::vector<double>& x, double f, double dt) {
  double re = 0, im = 0;
  for (size_t k = 0; k < x.size(); ++k) {
    re += x[k] * std::cos(2 * kPi * f * dt * static_cast<double>(k));
    im += x[k] * std::sin(2 * kPi * f * dt * static_cast<double>(k));
  }
  return 2.0 * std::hypot(re, im) / static_cast<double>(x.size());
}

TEST(Mpu6000, DigitalLowPassFilterAttenuatesAsConfigured) {
  // DLPF_CFG = 3: gyro bandwidth 42 Hz (RM 4.3), output 1 kHz. A 42 Hz rate comes out at -3 dB;
  // 4 Hz passes; 200 Hz is cut as a two-pole Butterworth sampled at fs cuts it,
  // 1/sqrt(1 + (tan(pi f/fs) / tan(pi fc/fs))^4) = 0.033. With DLPF_CFG = 0 (256 Hz, 8 kHz) the
  // same 200 Hz passes at 0.85.
  auto response = [](int cfg, double f_hz) {
    mpu6000 s;
    Bus bus = woken_on_spi(&s);
    bus.write(MPU6000_CONFIG, static_cast<uint8_t>(cfg), 0);
    const double amp_dps = 100;
    std::vector<double> out;
    const int64_t step = 125000;  // feed truth at the fastest internal rate
    for (int64_t t = 0; t < 1100 * kMs; t += step) {
      const double w = amp_dps * kDeg * std::sin(2 * kPi * f_hz * 1e-9 * static_cast<double>(t));
      hold_truth(&s, t, {0, 0, kG}, {w, 0, 0});
      if (t >= 100 * kMs && t % kMs == 0) {  // skip the settling; 1000 readings = whole cycles
        mpu6000_advance(&s, t);
        out.push_back(be16(bus.read(MPU6000_GYRO_XOUT_H, 2, t, 20000000), 0) / 131.0);
      }
    }
    return amplitude_at(out, f_hz, 1e-3) / amp_dps;
  };
  // Tolerance 0.01: quantisation (1 LSB in 13100) and the single-bin estimate are far below it.
  EXPECT_NEAR(response(3, 42), 1 / std::sqrt(2.0), 0.01);
  EXPECT_NEAR(response(3, 4), 1.0, 0.01);
  auto butterworth = [](double f, double fc, double fs) {
    return 1 / std::sqrt(1 + std::pow(std::tan(kPi * f / fs) / std::tan(kPi * fc / fs), 4));
  };
  EXPECT_NEAR(response(3, 200), butterworth(200, 42, 1000), 0.01);
  EXPECT_NEAR(response(0, 200), butterworth(200, 256, 8000), 0.01);
}

// Walks the INT pin through its events from t0 to t1 and returns (time, level) at each change.
std::vector<std::pair<int64_t, int>> pin_edges(mpu6000* s, int64_t t0, int64_t t1) {
  std::vector<std::pair<int64_t, int>> edges;
  mpu6000_advance(s, t0);
  int level = mpu6000_int_level(s);
  for (int64_t t = mpu6000_next_event_ns(s); t <= t1; t = mpu6000_next_event_ns(s)) {
    mpu6000_advance(s, t);
    const int now = mpu6000_int_level(s);
    if (now != level) edges.emplace_back(t, now);
    level = now;
  }
  return edges;
}

TEST(Mpu6000, DataReadyPinTiming) {
  mpu6000 s;
  Bus bus = woken_on_spi(&s);
  bus.write(MPU6000_CONFIG, 1, 0);       // DLPF on: gyro output 1 kHz
  bus.write(MPU6000_SMPLRT_DIV, 4, 0);   // 1 kHz / (1 + 4) = 200 Hz
  bus.write(MPU6000_INT_ENABLE, MPU6000_DATA_RDY, 0);
  EXPECT_EQ(mpu6000_sample_period_ns(&s), 5 * kMs);
  // Not latched, active high: a 50 us pulse per sample (RM 4.15).
  std::vector<std::pair<int64_t, int>> e = pin_edges(&s, 0, 30 * kMs);
  ASSERT_GE(e.size(), 10u);
  for (size_t i = 0; i + 2 < e.size(); i += 2) {
    EXPECT_EQ(e[i].second, 1);
    EXPECT_EQ(e[i + 1].first - e[i].first, 50000);
    EXPECT_EQ(e[i + 2].first - e[i].first, 5 * kMs);
  }
  // Active low (0x80): idles high, pulses low.
  bus.write(MPU6000_INT_PIN_CFG, MPU6000_INT_LEVEL_LOW, 30 * kMs);
  e = pin_edges(&s, 30 * kMs, 40 * kMs);
  ASSERT_GE(e.size(), 2u);
  EXPECT_EQ(e[0].second, 0);
  // Latched (0x20): held until INT_STATUS is read, which returns DATA_RDY and clears it.
  bus.write(MPU6000_INT_PIN_CFG, MPU6000_LATCH_INT_EN, 40 * kMs);
  bus.read1(MPU6000_INT_STATUS, 40 * kMs);
  mpu6000_advance(&s, 46 * kMs);
  EXPECT_EQ(mpu6000_int_level(&s), 1);
  EXPECT_EQ(mpu6000_next_event_ns(&s), INT64_MAX);
  mpu6000_advance(&s, 60 * kMs);
  EXPECT_EQ(mpu6000_int_level(&s), 1);
  EXPECT_EQ(bus.read1(MPU6000_WHO_AM_I, 60 * kMs), 0x68);
  EXPECT_EQ(mpu6000_int_level(&s), 1) << "without INT_RD_CLEAR only INT_STATUS clears";
  EXPECT_EQ(bus.read1(MPU6000_INT_STATUS, 60 * kMs, 20000000), MPU6000_DATA_RDY);
  EXPECT_EQ(mpu6000_int_level(&s), 0);
  // Clear on any read (0x10).
  bus.write(MPU6000_INT_PIN_CFG, MPU6000_LATCH_INT_EN | MPU6000_INT_RD_CLEAR, 60 * kMs);
  mpu6000_advance(&s, 66 * kMs);
  EXPECT_EQ(mpu6000_int_level(&s), 1);
  bus.read1(MPU6000_WHO_AM_I, 66 * kMs);
  EXPECT_EQ(mpu6000_int_level(&s), 0);
  // DLPF off, no divider: the gyro output rate, 8 kHz.
  bus.write(MPU6000_CONFIG, 0, 66 * kMs);
  bus.write(MPU6000_SMPLRT_DIV, 0, 66 * kMs);
  EXPECT_EQ(mpu6000_sample_period_ns(&s), 125000);
}

TEST(Mpu6000, FifoPacketsCountAndOverflow) {
  mpu6000 s;
  Bus bus = woken_on_spi(&s);
  bus.write(MPU6000_CONFIG, 1, 0);  // 1 kHz
  bus.write(MPU6000_INT_ENABLE, MPU6000_FIFO_OFLOW, 0);
  bus.write(MPU6000_FIFO_EN, MPU6000_FIFO_EN_ACCEL | MPU6000_FIFO_EN_XG | MPU6000_FIFO_EN_YG | MPU6000_FIFO_EN_ZG, 0);
  bus.write(MPU6000_USER_CTRL, MPU6000_USER_FIFO_EN | MPU6000_USER_FIFO_RESET, 0);
  hold_truth(&s, 0, {0.5 * kG, 0, kG}, {0, 0.1, 0});
  const int64_t t = 10 * kMs + 500000;  // woken at 0: 10 samples, at 1, 2, ... 10 ms
  const std::vector<uint8_t> n = bus.read(MPU6000_FIFO_COUNTH, 2, t, 20000000);
  EXPECT_EQ((n[0] << 8) | n[1], 10 * 12) << "12-byte accel+gyro packets";
  const std::vector<uint8_t> pkt = bus.read(MPU6000_FIFO_R_W, 12, t, 20000000);
  const std::vector<uint8_t> regs = bus.read(MPU6000_ACCEL_XOUT_H, 14, t, 20000000);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(pkt[static_cast<size_t>(i)], regs[static_cast<size_t>(i)]);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(pkt[static_cast<size_t>(6 + i)], regs[static_cast<size_t>(8 + i)]);
  EXPECT_EQ(be16(pkt, 0), 8192);
  // 1024 bytes hold 85 packets and a third: by 100 ms it has overflowed and holds exactly 1024.
  EXPECT_EQ(bus.read1(MPU6000_INT_STATUS, t, 20000000) & MPU6000_FIFO_OFLOW, 0);
  const std::vector<uint8_t> full = bus.read(MPU6000_FIFO_COUNTH, 2, 100 * kMs, 20000000);
  EXPECT_EQ((full[0] << 8) | full[1], 1024);
  EXPECT_EQ(bus.read1(MPU6000_INT_STATUS, 100 * kMs, 20000000) & MPU6000_FIFO_OFLOW, MPU6000_FIFO_OFLOW);
  bus.write(MPU6000_USER_CTRL, MPU6000_USER_FIFO_EN | MPU6000_USER_FIFO_RESET, 100 * kMs);
  const std::vector<uint8_t> empty = bus.read(MPU6000_FIFO_COUNTH, 2, 100 * kMs, 20000000);
  EXPECT_EQ((empty[0] << 8) | empty[1], 0);
}

TEST(Mpu6000, BusSpeedLimitsAndInterfaces) {
  mpu6000 s;
  const mpu6000_config c = clean_config();
  mpu6000_init(&s, &c, 0);
  Bus bus{&s, false};
  // PS 6.5: writes only at <= 1 MHz: waking it at 8 MHz does nothing.
  bus.write(MPU6000_PWR_MGMT_1, 0, 0, 8000000);
  EXPECT_EQ(bus.read1(MPU6000_PWR_MGMT_1, 0), 0x40);
  // Configuration registers read at 20 MHz give garbage; sensor registers do not, up to 20 MHz.
  int wrong = 0;
  for (int i = 0; i < 16; ++i) wrong += bus.read1(MPU6000_WHO_AM_I, 0, 20000000) != 0x68;
  EXPECT_GE(wrong, 12) << "garbage matches 0x68 only by chance, 1 in 256";
  bus.write(MPU6000_PWR_MGMT_1, 0, 0);
  hold_truth(&s, 0, {0, 0, kG}, {0, 0, 0});
  EXPECT_EQ(be16(bus.read(MPU6000_ACCEL_XOUT_H, 6, kMs, 20000000), 4), 16384);
  int bad = 0;
  for (int i = 0; i < 16; ++i) bad += be16(bus.read(MPU6000_ACCEL_XOUT_H, 6, kMs, 25000000), 4) != 16384;
  EXPECT_GE(bad, 15);
  // The MPU-6000 answers I2C until I2C_IF_DIS; then it NACKs.
  uint8_t reg = MPU6000_WHO_AM_I, v = 0;
  EXPECT_EQ(mpu6000_i2c_write(&s, &reg, 1, kMs), 0);
  EXPECT_EQ(mpu6000_i2c_read(&s, &v, 1, kMs), 0);
  EXPECT_EQ(v, 0x68);
  bus.write(MPU6000_USER_CTRL, MPU6000_USER_I2C_IF_DIS, kMs);
  EXPECT_EQ(mpu6000_i2c_write(&s, &reg, 1, kMs), -1);
  // The MPU-6050 has no SPI at all.
  mpu6000 s50;
  const mpu6000_config c50 = clean_config(MPU6000_VARIANT_6050);
  mpu6000_init(&s50, &c50, 0);
  Bus spi50{&s50, false};
  EXPECT_EQ(spi50.read1(MPU6000_WHO_AM_I, 0), 0xFF);
  Bus i2c50{&s50, true};
  EXPECT_EQ(i2c50.read1(MPU6000_WHO_AM_I, 0), 0x68);
}

// ---------- MPU-6000: error statistics ----------

TEST(Mpu6000, AtRestReadsOneGAndZeroRateWithinTheConfiguredBias) {
  // Datasheet defaults (PS tables 6.1/6.2). Over 20 parts, the mean readings at rest scatter about
  // +1 g up and 0 deg/s by the configured turn-on bias (plus scale error on the 1 g axis).
  std::vector<double> gyro_dev, accel_z_dev;
  mpu6000_config c;
  mpu6000_default_config(&c, MPU6000_VARIANT_6000);
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    c.seed = seed;
    mpu6000 s;
    start_at_rest(&s, c, 3);
    double sum[6] = {};
    const int n = 200;
    for (int k = 1; k <= n; ++k) {
      mpu6000_advance(&s, k * kMs);
      for (int i = 0; i < 6; ++i) {
        const int base = i < 3 ? 0 : 8;
        const int j = i % 3;
        sum[i] += shown16(s, static_cast<size_t>(base + 2 * j));
      }
    }
    for (int i = 0; i < 3; ++i) gyro_dev.push_back(sum[3 + i] / n / 131.0 * kDeg);
    accel_z_dev.push_back(sum[2] / n / 16384.0 * kG - kG);
  }
  auto rms = [](const std::vector<double>& v) {
    double q = 0;
    for (double x : v) q += x * x;
    return std::sqrt(q / static_cast<double>(v.size()));
  };
  // 60 gyro means: the RMS estimates the bias sd to ~1/sqrt(120) = 9 %; +-30 % is 3.3 sd. The
  // averaging noise (0.0036 deg/s over 200 samples at 42 Hz) adds nothing visible.
  EXPECT_NEAR(rms(gyro_dev) / c.gyro.turn_on_bias[0], 1.0, 0.3);
  // Accel Z: bias sd 80/3 mg and scale sd 1 % of 1 g, combined; 20 parts: +-50 % is ~3.2 sd.
  const double sd_z = std::hypot(c.accel.turn_on_bias[2], c.accel.scale_error * kG);
  EXPECT_NEAR(rms(accel_z_dev) / sd_z, 1.0, 0.5);
}

// Overlapping Allan variance of x (sample period dt) at cluster size m.
double allan_variance(const std::vector<double>& cumsum, size_t m) {
  const size_t n = cumsum.size() - 1;
  double acc = 0;
  size_t count = 0;
  for (size_t k = 0; k + 2 * m <= n; ++k) {
    const double a = (cumsum[k + m] - cumsum[k]) / static_cast<double>(m);
    const double b = (cumsum[k + 2 * m] - cumsum[k + m]) / static_cast<double>(m);
    acc += (b - a) * (b - a);
    ++count;
  }
  return acc / (2.0 * static_cast<double>(count));
}

TEST(Mpu6000, GyroAllanDeviationShowsWhiteNoiseAndBiasWalk) {
  // A stationary gyro for 2000 s at 1 kHz (DLPF 188 Hz), read straight from its data registers.
  // Configured: white noise density N = 0.005 deg/s/sqrt(Hz) (datasheet) and, to make the walk
  // show within a short run, bias walk K = 1e-4 rad/s/sqrt(s). Expected (one-sided density, see
  // imu_error.h): AVAR(tau) = N^2 / (2 tau) + K^2 tau / 3. At tau = 0.1 s white noise dominates
  // (walk 0.9 %); at tau = 20 s the walk does (white 0.3 %).
  mpu6000_config c = clean_config();
  c.gyro.noise_density = 0.005 * kDeg;
  c.gyro.bias_walk = 1e-4;
  c.seed = 7;
  mpu6000 s;
  start_at_rest(&s, c, 1);
  const size_t n = 2000000;
  std::vector<std::vector<double>> cum(3, std::vector<double>(n + 1, 0.0));
  for (size_t k = 1; k <= n; ++k) {
    mpu6000_advance(&s, static_cast<int64_t>(k) * kMs);
    for (size_t i = 0; i < 3; ++i) {
      const int16_t v = shown16(s, 8 + 2 * i);
      cum[i][k] = cum[i][k - 1] + v / 131.0 * kDeg;
    }
  }
  const double N = c.gyro.noise_density, K = c.gyro.bias_walk;
  for (double tau : {0.1, 20.0}) {
    double avar = 0;
    for (size_t i = 0; i < 3; ++i) avar += allan_variance(cum[i], static_cast<size_t>(tau * 1000)) / 3;
    const double expected = N * N / (2 * tau) + K * K * tau / 3;
    // 10 %, the brief's bound: at tau = 20 s the three axes give ~3 x 65 effective degrees of
    // freedom (overlapping estimator, 100 clusters each), a 1-sd error of ~5 % in deviation.
    EXPECT_NEAR(std::sqrt(avar / expected), 1.0, 0.10) << "tau " << tau;
  }
}

// ---------- IMU truth ----------

TEST(ImuTruth, LeverArmReadsCentripetalAndFreeFallReadsZero) {
  dInitODE2(0);
  dWorldID world = dWorldCreate();
  dWorldSetGravity(world, 0, 0, -9.81);
  dBodyID body = dBodyCreate(world);
  dMass m;
  dMassSetSphereTotal(&m, 1.0, 0.1);
  dBodySetMass(body, &m);
  const double w = 5.0;  // rad/s about z, a principal axis: no torque, constant rate
  dBodySetAngularVel(body, 0, 0, w);
  sear::ImuMount mount;
  mount.position_m = {0.1, 0, 0};
  sear::ImuTruth truth(mount, {0, 0, -9.81});
  const double h = 0.001;
  sear::ImuSample s;
  for (int k = 0; k < 200; ++k) {
    dWorldStep(world, h);
    s = truth.update(body, h);
  }
  // Free fall: the body accelerates at g, so its specific force is only the centripetal term,
  // -w^2 r = -2.5 m/s^2 along the radius (the sensor's x, which turns with the body).
  EXPECT_NEAR(s.specific_force_mps2.x(), -w * w * 0.1, 1e-9);
  EXPECT_NEAR(s.specific_force_mps2.y(), 0, 1e-9);
  EXPECT_NEAR(s.specific_force_mps2.z(), 0, 1e-9);
  EXPECT_NEAR(s.rate_radps.z(), w, 1e-12);
  // Held still by a fixed joint: +1 g up. A sensor mounted turned +90 degrees about the body's y
  // has its x pointing down, so it reads the 1 g on x, negative.
  dBodySetAngularVel(body, 0, 0, 0);
  dBodySetLinearVel(body, 0, 0, 0);
  dJointID fix = dJointCreateFixed(world, nullptr);
  dJointAttach(fix, body, nullptr);
  dJointSetFixed(fix);
  sear::ImuMount tilted;
  tilted.body_from_sensor = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  sear::ImuTruth still(tilted, {0, 0, -9.81});
  for (int k = 0; k < 50; ++k) {
    dWorldStep(world, h);
    s = still.update(body, h);
  }
  const Eigen::Matrix3d rb = still.world_from_sensor(body);
  const Eigen::Vector3d expected = rb.transpose() * Eigen::Vector3d(0, 0, 9.81);
  EXPECT_NEAR((s.specific_force_mps2 - expected).norm(), 0, 1e-3);  // joint-solver residue
  EXPECT_NEAR(s.specific_force_mps2.x(), -9.81, 1e-3);  // it spun about z only: still level
  dJointDestroy(fix);
  dWorldDestroy(world);
  // Angular acceleration: a tangential alpha x r on top.
  sear::ImuMount arm;
  arm.position_m = {0.1, 0, 0};
  const sear::ImuSample k = sear::imu_from_kinematics(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(),
                                                      Eigen::Vector3d::Zero(), {0, 0, 3.0}, arm, Eigen::Vector3d::Zero());
  EXPECT_NEAR(k.specific_force_mps2.y(), 0.3, 1e-12);
}

// ---------- Magnetic field ----------

TEST(MagneticField, Wmm2025MatchesNoaaSoftware) {
  // Reference: NOAA's WMM2025 C software (through the wmm2025 Python binding's test) at
  // 65 N, 85 E, 0 km, 2026.5: X 8739.604, Y 2229.254, Z 60367.156 nT, D 14.3096, I 81.5023 deg.
  // Same coefficients, same equations: agreement to 0.05 nT is rounding.
  const Eigen::Vector3d ned = sear::wmm2025_ned_T({65, 85, 0}, 2026.5) * 1e9;
  EXPECT_NEAR(ned.x(), 8739.604, 0.05);
  EXPECT_NEAR(ned.y(), 2229.254, 0.05);
  EXPECT_NEAR(ned.z(), 60367.156, 0.05);
  const sear::GeomagneticElements e = sear::wmm2025_elements({65, 85, 0}, 2026.5);
  EXPECT_NEAR(e.declination_rad / kDeg, 14.3096, 1e-3);
  EXPECT_NEAR(e.inclination_rad / kDeg, 81.5023, 1e-3);
  const Eigen::Vector3d enu = sear::field_enu_T(e);
  EXPECT_NEAR((enu - Eigen::Vector3d(ned.y(), ned.x(), -ned.z()) * 1e-9).norm(), 0, 1e-12);
}

// ---------- Compasses ----------

// Register reads and writes over I2C as a driver makes them: the register pointer first.
template <class Dev>
std::vector<uint8_t> i2c_read(int (*write)(Dev*, const uint8_t*, size_t, int64_t),
                              int (*read)(Dev*, uint8_t*, size_t, int64_t), Dev* s, uint8_t reg, size_t n, int64_t t) {
  std::vector<uint8_t> out(n);
  EXPECT_EQ(write(s, &reg, 1, t), 0);
  EXPECT_EQ(read(s, out.data(), n, t), 0);
  return out;
}
template <class Dev>
void i2c_write(int (*write)(Dev*, const uint8_t*, size_t, int64_t), Dev* s, uint8_t reg, uint8_t v, int64_t t) {
  const uint8_t d[2] = {reg, v};
  EXPECT_EQ(write(s, d, 2, t), 0);
}

// A compass config for the register tests: the datasheet's, without noise.
template <class Config>
Config noiseless(void (*defaults)(Config*)) {
  Config c;
  defaults(&c);
  c.noise_sd_T = 0;
  return c;
}

std::vector<uint8_t> hmc_read(hmc5883l* s, uint8_t reg, size_t n, int64_t t) {
  return i2c_read(hmc5883l_i2c_write, hmc5883l_i2c_read, s, reg, n, t);
}
void hmc_write(hmc5883l* s, uint8_t reg, uint8_t v, int64_t t) { i2c_write(hmc5883l_i2c_write, s, reg, v, t); }

// Heading of the sensor's x axis clockwise from true north, from a level compass's x and y
// (x forward, y left, z up) and the declination.
double heading_deg(double x, double y, double declination_rad) {
  double h = (std::atan2(y, x) + declination_rad) / kDeg;
  while (h < 0) h += 360;
  while (h >= 360) h -= 360;
  return h;
}
double angle_diff_deg(double a, double b) { return std::remainder(a - b, 360.0); }

TEST(Hmc5883l, RegistersTimingAndOverflow) {
  hmc5883l s;
  const hmc5883l_config c = noiseless(hmc5883l_default_config);
  hmc5883l_init(&s, &c, 0);
  // Identification 'H' '4' '3'; past 12 the pointer wraps to 0 (CRA 0x10, CRB 0x20, MR 0x01).
  const std::vector<uint8_t> id = hmc_read(&s, 0x0A, 6, 0);
  EXPECT_EQ(id, (std::vector<uint8_t>{'H', '4', '3', 0x10, 0x20, 0x01}));
  // 0.1, 0.2, 0.3 gauss at gain 1 (1090 LSB/G): X 109, Y 218, Z 327, sent X Z Y, MSB first.
  const double field[3] = {1e-5, 2e-5, 3e-5};
  hmc5883l_set_truth(&s, 0, field);
  hmc_write(&s, HMC5883L_MODE, 0x01, kMs);  // single measurement
  EXPECT_EQ(hmc5883l_next_event_ns(&s), kMs + 6000000);
  EXPECT_EQ(hmc_read(&s, HMC5883L_STATUS, 1, kMs + 5900000)[0] & HMC5883L_RDY, 0);
  EXPECT_EQ(hmc5883l_drdy_level(&s), 1);
  EXPECT_EQ(hmc_read(&s, HMC5883L_STATUS, 1, kMs + 6000000)[0] & HMC5883L_RDY, HMC5883L_RDY);
  EXPECT_EQ(hmc5883l_drdy_level(&s), 0) << "DRDY low for 250 us as the data lands";
  EXPECT_EQ(hmc5883l_next_event_ns(&s), kMs + 6250000);
  std::vector<uint8_t> d = hmc_read(&s, 0x03, 8, 8 * kMs);
  EXPECT_EQ(be16(d, 0), 109);
  EXPECT_EQ(be16(d, 2), 327);
  EXPECT_EQ(be16(d, 4), 218);
  EXPECT_EQ(be16(d, 6), 109) << "after 0x08 the pointer rolls back to 0x03";
  EXPECT_EQ(hmc_read(&s, HMC5883L_STATUS, 1, 8 * kMs)[0] & HMC5883L_RDY, 0) << "all six read: RDY cleared";
  EXPECT_EQ(hmc_read(&s, HMC5883L_MODE, 1, 8 * kMs)[0] & 3, 3) << "idle after a single measurement";
  // 5 gauss at gain 1 overflows (5450 > 2047): -4096. Gain 7 (230 LSB/G) takes effect from the
  // second measurement after the change (CRB description).
  const double strong[3] = {5e-4, 0, 0};
  hmc5883l_set_truth(&s, 10 * kMs, strong);
  hmc_write(&s, HMC5883L_CONFIG_B, 7 << 5, 10 * kMs);
  hmc_write(&s, HMC5883L_MODE, 0x01, 10 * kMs);
  EXPECT_EQ(be16(hmc_read(&s, 0x03, 6, 20 * kMs), 0), HMC5883L_OVERFLOW_CODE);
  hmc_write(&s, HMC5883L_MODE, 0x01, 20 * kMs);
  EXPECT_EQ(be16(hmc_read(&s, 0x03, 6, 30 * kMs), 0), 1150);
  // Every gain of table 9 (LSB/G 1370, 1090, 820, 660, 440, 390, 330, 230) on 0.4 G, each read
  // from the second measurement after the change.
  const double lsb[8] = {1370, 1090, 820, 660, 440, 390, 330, 230};
  const double mid[3] = {4e-5, 0, 0};
  hmc5883l_set_truth(&s, 30 * kMs, mid);
  int64_t t = 30 * kMs;
  for (int gn = 0; gn < 8; ++gn) {
    hmc_write(&s, HMC5883L_CONFIG_B, static_cast<uint8_t>(gn << 5), t);
    hmc_write(&s, HMC5883L_MODE, 0x01, t);
    hmc_write(&s, HMC5883L_MODE, 0x01, t + 7 * kMs);
    EXPECT_EQ(be16(hmc_read(&s, 0x03, 6, t + 14 * kMs), 0), std::lround(0.4 * lsb[gn])) << "GN " << gn;
    t += 20 * kMs;
  }
  hmc5883l_set_truth(&s, t, strong);
  // Continuous at 75 Hz: a partial read locks the outputs until all six bytes are read.
  hmc_write(&s, HMC5883L_CONFIG_A, 6 << 2, t);
  hmc_write(&s, HMC5883L_MODE, 0x00, t);
  hmc_read(&s, 0x03, 2, t + 10 * kMs);
  EXPECT_TRUE(hmc_read(&s, HMC5883L_STATUS, 1, t + 10 * kMs)[0] & HMC5883L_LOCK);
  const double other[3] = {1e-5, 0, 0};
  hmc5883l_set_truth(&s, t + 10 * kMs, other);
  // 60 ms and four results later X still holds the locked 5 G sample, not the new 0.1 G.
  EXPECT_EQ(be16(hmc_read(&s, 0x03, 2, t + 70 * kMs), 0), 1150);
  hmc_read(&s, 0x05, 4, t + 70 * kMs);  // the rest of the six: unlocked
  EXPECT_EQ(be16(hmc_read(&s, 0x03, 6, t + 85 * kMs), 0), 23) << "0.1 G at 230 LSB/G";
}

TEST(Hmc5883l, HeadingWithinADegreeWhenLevelAndTiltShowsAsOnARobot) {
  const sear::GeomagneticElements e = sear::wmm2025_elements({48.15, 11.58, 520}, 2026.0);  // Munich
  const Eigen::Vector3d b_enu = sear::field_enu_T(e);
  hmc5883l_config c;
  hmc5883l_default_config(&c);
  auto read_heading = [&](const Eigen::Matrix3d& world_from_sensor, uint64_t seed) {
    hmc5883l s;
    c.seed = seed;
    hmc5883l_init(&s, &c, 0);
    hmc_write(&s, HMC5883L_CONFIG_A, 0x60 | (6 << 2), 0);  // 8-sample average, 75 Hz
    hmc_write(&s, HMC5883L_CONFIG_B, 0, 0);                // gain 0: 1370 LSB/G, +-0.88 G
    const Eigen::Vector3d b = sear::field_in_sensor_T(b_enu, world_from_sensor);
    hmc5883l_set_truth(&s, 0, b.data());
    hmc_write(&s, HMC5883L_MODE, 0x00, 0);
    double x = 0, y = 0;
    for (int k = 1; k <= 10; ++k) {
      const std::vector<uint8_t> d = hmc_read(&s, 0x03, 6, k * 14 * kMs);
      x += be16(d, 0);
      y += be16(d, 4);
    }
    return heading_deg(x, y, e.declination_rad);
  };
  // Level, x forward, at twelve true headings (heading H: yaw = 90 - H counter-clockwise from east).
  // Noise: 2 mG / sqrt(8 x 10) over a ~0.2 G horizontal field is 0.07 deg; quantisation 0.2 deg.
  for (int hdg = 0; hdg < 360; hdg += 30) {
    const Eigen::Matrix3d r = Eigen::AngleAxisd((90 - hdg) * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    EXPECT_NEAR(angle_diff_deg(read_heading(r, static_cast<uint64_t>(hdg) + 1), hdg), 0, 1.0) << hdg;
  }
  // Pitched 20 deg nose-up, heading east: the steep Munich field (I ~ 64 deg) leaks into x. The
  // naive heading is off by what geometry predicts, tens of degrees, not by noise.
  const Eigen::Matrix3d pitched = Eigen::AngleAxisd(0, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                                  Eigen::AngleAxisd(-20 * kDeg, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d bs = sear::field_in_sensor_T(b_enu, pitched);
  const double predicted = heading_deg(bs.x(), bs.y(), e.declination_rad);
  const double naive = read_heading(pitched, 99);
  EXPECT_NEAR(angle_diff_deg(naive, predicted), 0, 1.0);
  EXPECT_GT(std::abs(angle_diff_deg(naive, 90)), 10.0);
}

std::vector<uint8_t> qmc_read(qmc5883l* s, uint8_t reg, size_t n, int64_t t) {
  return i2c_read(qmc5883l_i2c_write, qmc5883l_i2c_read, s, reg, n, t);
}
void qmc_write(qmc5883l* s, uint8_t reg, uint8_t v, int64_t t) { i2c_write(qmc5883l_i2c_write, s, reg, v, t); }
int16_t le16(const std::vector<uint8_t>& d, size_t i) { return static_cast<int16_t>(d[i] | (d[i + 1] << 8)); }

TEST(Qmc5883l, RegistersAndHowFirmwareTellsItFromAnHmc) {
  qmc5883l s;
  const qmc5883l_config c = noiseless(qmc5883l_default_config);
  qmc5883l_init(&s, &c, 0);
  // Detection: chip ID 0xFF at 0x0D; no 'H43' where the HMC keeps it.
  EXPECT_EQ(qmc_read(&s, QMC5883L_CHIP_ID, 1, 0)[0], 0xFF);
  EXPECT_NE(qmc_read(&s, 0x0A, 3, 0), (std::vector<uint8_t>{'H', '4', '3'}));
  const double field[3] = {1e-5, -2e-5, 3e-5};  // 0.1, -0.2, 0.3 G
  qmc5883l_set_truth(&s, 0, field);
  qmc_write(&s, QMC5883L_SET_RESET, 0x01, 0);
  qmc_write(&s, QMC5883L_CONTROL_1, 0x01 | (1 << 2), 0);  // continuous, 50 Hz, +-2 G, OSR 512
  EXPECT_EQ(qmc_read(&s, QMC5883L_STATUS, 1, 19 * kMs)[0] & QMC5883L_DRDY, 0);
  EXPECT_EQ(qmc_read(&s, QMC5883L_STATUS, 1, 20 * kMs)[0] & QMC5883L_DRDY, QMC5883L_DRDY);
  std::vector<uint8_t> d = qmc_read(&s, 0x00, 6, 20 * kMs);  // X Y Z, LSB first, 12000 LSB/G
  EXPECT_EQ(le16(d, 0), 1200);
  EXPECT_EQ(le16(d, 2), -2400);
  EXPECT_EQ(le16(d, 4), 3600);
  EXPECT_EQ(qmc_read(&s, QMC5883L_STATUS, 1, 20 * kMs)[0] & QMC5883L_DRDY, 0) << "a data read clears DRDY";
  // Skipped results set DOR; 8 G range: 3000 LSB/G; 3 G saturates at +-2 G range with OVL.
  EXPECT_EQ(qmc_read(&s, QMC5883L_STATUS, 1, 70 * kMs)[0] & QMC5883L_DOR, QMC5883L_DOR);
  const double strong[3] = {3e-4, 0, 0};
  qmc5883l_set_truth(&s, 70 * kMs, strong);
  EXPECT_EQ(qmc_read(&s, QMC5883L_STATUS, 1, 90 * kMs)[0] & QMC5883L_OVL, QMC5883L_OVL);
  EXPECT_EQ(le16(qmc_read(&s, 0x00, 2, 90 * kMs), 0), 32767);
  qmc_write(&s, QMC5883L_CONTROL_1, 0x01 | (1 << 2) | (1 << 4), 90 * kMs);
  EXPECT_EQ(le16(qmc_read(&s, 0x00, 2, 110 * kMs), 0), 9000);
  // Pointer roll-over: with ROL_PNT a 7-byte read wraps from 06H to 00H.
  qmc_write(&s, QMC5883L_CONTROL_2, QMC5883L_ROL_PNT, 110 * kMs);
  d = qmc_read(&s, 0x00, 9, 130 * kMs);
  EXPECT_EQ(d[7], d[0]);
  EXPECT_EQ(d[8], d[1]);
  // Soft reset: back to standby with every control register 0.
  qmc_write(&s, QMC5883L_CONTROL_2, QMC5883L_SOFT_RST, 130 * kMs);
  EXPECT_EQ(qmc_read(&s, QMC5883L_CONTROL_1, 1, 130 * kMs)[0], 0);
  EXPECT_EQ(qmc5883l_next_event_ns(&s), INT64_MAX);
}

}  // namespace
