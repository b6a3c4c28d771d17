// The position sensors end to end: a firmware reads the HMC5883L over I2C, the MPU-6000 over SPI
// and two quadrature encoders on pin-change interrupts while a script drives the rover, and what
// it prints is held against the run's own trace (the physics' truth).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "firmware_run.hpp"

namespace sear::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Reading {
  double mag[3];    // X, Z, Y as the part sends them
  double imu[6];    // accel x y z, gyro x y z
  long enc[2];      // left, right
};

struct TraceRow {
  double yaw, wz, wheel[2];
};

// The project: the rover on flat ground at Cambridge, turned to yaw_deg, driven in an arc by its
// script from 1 s to 3 s and then braked, with the probe reading everything.
std::string project(double yaw_deg) {
  std::ostringstream p;
  p << "<project name=\"position\">\n  <run duration=\"4\" seed=\"3\" trace_rate=\"1000\"/>\n"
    << "  <world step=\"0.001\">\n    <gps_origin latitude=\"52.2053\" longitude=\"0.1218\" altitude=\"12\"/>\n"
    << "    <magnetic declination_deg=\"0.9\"/>\n    <terrain type=\"flat\"/>\n  </world>\n"
    << "  <robot file=\"" << SEAR_ASSET_DIR << "/robots/rover.xml\">\n    <pose x=\"0\" y=\"0\" yaw_deg=\"" << yaw_deg
    << "\"/>\n    <script>\n      <motor t=\"1\" name=\"left\" duty=\"0.3\" dir=\"forward\"/>\n"
    << "      <motor t=\"1\" name=\"right\" duty=\"0.9\" dir=\"forward\"/>\n"
    << "      <motor t=\"3\" name=\"left\" duty=\"0\" dir=\"brake\"/>\n      <motor t=\"3\" name=\"right\" duty=\"0\" dir=\"brake\"/>\n"
    << "    </script>\n    <mcu name=\"main\">\n      <firmware executable=\"" << POSITION_PROBE << "\"/>\n"
    << "      <hmc5883l name=\"compass\" pos=\"0 0 0.1\"/>\n      <mpu6000 name=\"imu\" cs=\"53\" pos=\"0 0 0.05\"/>\n"
    << "      <quadrature_encoder name=\"enc_l\" wheel=\"left\" a=\"64\" b=\"65\" cycles_per_rev=\"90\"/>\n"
    << "      <quadrature_encoder name=\"enc_r\" wheel=\"right\" a=\"66\" b=\"67\" cycles_per_rev=\"90\"/>\n"
    << "    </mcu>\n  </robot>\n</project>\n";
  return p.str();
}

std::map<long, Reading> readings(const SearRun& run) {
  std::map<long, Reading> out;
  for (const auto& line : lines_of(run.file("rover.main.console.log"))) {
    long t = 0;
    Reading r{};
    if (std::sscanf(line.c_str(), "%*s %ld mag %lf %lf %lf imu %lf %lf %lf %lf %lf %lf enc %ld %ld", &t, &r.mag[0],
                    &r.mag[1], &r.mag[2], &r.imu[0], &r.imu[1], &r.imu[2], &r.imu[3], &r.imu[4], &r.imu[5], &r.enc[0],
                    &r.enc[1]) == 12)
      out[t] = r;
  }
  return out;
}

// Rows of the 1 kHz trace by millisecond: yaw, yaw rate and the wheels' spin.
std::vector<TraceRow> trace(const SearRun& run) {
  std::vector<TraceRow> rows;
  const auto lines = lines_of(run.file("trace_rover.csv"));
  for (std::size_t i = 1; i < lines.size(); ++i) {
    double v[16];
    std::istringstream in(lines[i]);
    std::string cell;
    for (int c = 0; c < 16 && std::getline(in, cell, ','); ++c) v[c] = std::stod(cell);
    rows.push_back({v[6], v[12], {v[14], v[15]}});
  }
  return rows;
}

class PositionRun : public testing::TestWithParam<double> {};

TEST_P(PositionRun, CompassImuAndEncodersAgreeWithThePhysics) {
  TempDir dir;
  const SearRun run = run_sear(dir, project(GetParam()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto r = readings(run);
  const auto rows = trace(run);
  ASSERT_GE(r.size(), 39u);
  ASSERT_GE(rows.size(), 4000u);

  // Compass, level and still (before 1 s and after 3.3 s): heading = atan2(Y, X) for an X-forward,
  // Y-left sensor, plus the declination, against the trace's yaw (counter-clockwise from east).
  // Its noise is 2 mG a sample against 0.19 G horizontal at Cambridge (0.6 deg), so the mean of
  // the still samples lies within the datasheet-derived 1 degree.
  double error_sum = 0;
  int still = 0;
  for (const auto& [t, reading] : r) {
    if (t > 900 && t < 3300) continue;
    const double magnetic = std::atan2(reading.mag[2], reading.mag[0]) * 180 / kPi;
    const double truth = 90 - rows[static_cast<std::size_t>(t)].yaw * 180 / kPi;
    const double error = std::remainder(magnetic + 0.9 - truth, 360.0);
    EXPECT_LT(std::abs(error), 3.0) << "at " << t << " ms";
    error_sum += error;
    ++still;
  }
  EXPECT_LT(std::abs(error_sum / still), 1.0);

  // Accelerometer at rest: +1 g on z (16384 LSB at +-2 g), within the datasheet's 3-sigma zero-g
  // offset (80 mg) and sensitivity tolerance (3 %): 16384 * (1 +- 0.03) +- 1311 LSB.
  EXPECT_NEAR(r.at(500).imu[2], 16384, 16384 * 0.03 + 1311);
  // Gyro z while turning, less its reading at rest (the turn-on bias, up to 20 deg/s): the truth's
  // yaw rate within the 3 % sensitivity tolerance and 1 deg/s of noise and filter lag.
  const double rest = r.at(500).imu[5];
  const double turning = r.at(2500).imu[5];
  const double truth_dps = rows[2500].wz * 180 / kPi;
  EXPECT_GT(std::abs(truth_dps), 20.0);
  EXPECT_NEAR((turning - rest) / 131.0, truth_dps, std::abs(truth_dps) * 0.03 + 1.0);

  // Encoders: every edge of both channels counted, 4 x 90 per wheel turn, against the wheel
  // angle integrated from the 1 kHz trace (trapezoids: within a count over the run).
  double angle[2] = {0, 0};
  for (std::size_t i = 1; i < rows.size(); ++i) {
    for (int w = 0; w < 2; ++w) angle[w] += 0.5e-3 * (rows[i].wheel[w] + rows[i - 1].wheel[w]);
    const long t = static_cast<long>(i);
    if (t % 100 || !r.count(t)) continue;
    for (int w = 0; w < 2; ++w)
      EXPECT_NEAR(static_cast<double>(r.at(t).enc[w]), angle[w] / (2 * kPi / 360), 1.5) << "wheel " << w << " at " << t << " ms";
  }
  EXPECT_GT(r.rbegin()->second.enc[1], 360);  // the right wheel turned more than once
}

// Facing east, north-north-west and south-west.
INSTANTIATE_TEST_SUITE_P(Headings, PositionRun, testing::Values(0.0, 110.0, 225.0));

// The MPU-6000's latched data-ready interrupt at 100 Hz (SMPLRT_DIV 9 of its 1 kHz rate), read
// and so cleared over SPI (tests/firmware/int_clear_probe.c): the falling INT edge's interrupt
// runs within the transfer that clears INT, as the chip takes it during the busy-wait on SPIF,
// never at a later HAL call; every read clears one assertion, and from the end of the part's
// start-up to 0.5 s at least 30 samples fall due.
TEST(ImuInterrupt, TheEdgeAReadCausesRunsBeforeTheTransferReturns) {
  TempDir dir;
  std::ostringstream p;
  p << "<project name=\"int_clear\">\n  <run duration=\"0.6\" seed=\"1\"/>\n"
    << "  <world step=\"0.001\">\n    <terrain type=\"flat\"/>\n  </world>\n"
    << "  <robot file=\"" << SEAR_ASSET_DIR << "/robots/rover.xml\">\n    <pose x=\"0\" y=\"0\"/>\n"
    << "    <mcu name=\"main\">\n      <firmware executable=\"" << INT_CLEAR_PROBE << "\"/>\n"
    << "      <mpu6000 name=\"imu\" cs=\"53\" int=\"63\" pos=\"0 0 0.05\"/>\n"
    << "    </mcu>\n  </robot>\n</project>\n";
  const SearRun run = run_sear(dir, p.str());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  unsigned long reads = 0, late = 0, falls = 0;
  bool found = false;
  for (const auto& line : lines_of(run.file("rover.main.console.log")))
    found = found || std::sscanf(line.c_str(), "%*s reads %lu late %lu falls %lu", &reads, &late, &falls) == 3;
  ASSERT_TRUE(found) << run.file("rover.main.console.log");
  EXPECT_GE(reads, 30u);
  EXPECT_LE(reads, 50u);  // 100 Hz over at most 0.5 s
  EXPECT_EQ(late, 0u);
  EXPECT_EQ(falls, reads);
}

}  // namespace
}  // namespace sear::test
