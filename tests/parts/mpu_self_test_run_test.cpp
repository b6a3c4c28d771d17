// The MPU-6000's self-test end to end: a firmware runs the gyro self-test over SPI as InvenSense's
// driver does, and the response it measures is the factory trim its SELF_TEST_X code encodes
// times 1 + the project's `self_test_error`, so a project can give a healthy part or one that
// fails (beyond -14 %..+14 %, PS 6.1).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "devices/mpu6000.h"
#include "firmware_run.hpp"

namespace sear::test {
namespace {

constexpr double kLsbPerDps = 131.0;  // at +-250 deg/s (PS 6.1)

// The response over the trim, as the driver computes it: 1 for a part exactly at its trim.
double response_over_trim(double self_test_error) {
  TempDir dir;
  const std::string mcu = std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + MPU_SELF_TEST_PROBE +
                          "\"/>\n      <mpu6000 name=\"imu\" cs=\"53\" pos=\"0 0 0.05\" self_test_error=\"" +
                          std::to_string(self_test_error) + "\"/>\n    </mcu>\n";
  const SearRun run = run_sear(dir, rover_project(mcu, "", 0.3), "--quiet");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  long response = 0;
  unsigned code = 0;
  for (const auto& line : lines_of(run.file("rover.main.console.log")))
    if (std::sscanf(line.c_str(), "%*s self-test x %ld lsb, code %u", &response, &code) == 2) break;
  EXPECT_GE(code, 1u);  // a trimmed part: 1..31
  EXPECT_LE(code, 31u);
  return static_cast<double>(response) / (mpu6000_gyro_trim_dps(static_cast<std::uint8_t>(code), 0) * kLsbPerDps);
}

// Within 3 %: the gyro's sensitivity tolerance (PS 6.1: +-3 %), which the model draws per part
// and applies to what it senses, the self-test's response included; the noise of two means of 50
// readings at 44 Hz is a few LSB of a response of some 6000.
TEST(Mpu6000SelfTestRun, TheResponseIsTheTrimTimesOnePlusTheProjectsError) {
  EXPECT_NEAR(response_over_trim(0.0), 1.0, 0.03);
  EXPECT_NEAR(response_over_trim(-0.2), 0.8, 0.03);  // fails InvenSense's test
  EXPECT_NEAR(response_over_trim(0.5), 1.5, 0.03 * 1.5);
}

}  // namespace
}  // namespace sear::test
