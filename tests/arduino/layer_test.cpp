// The Arduino layer (hal/arduino) end to end: a clean-room sketch preprocessed by arduino-builder,
// built against the layer and Debian's core, run by `sear` on the rover 1.00 m from a wall with an
// HC-SR04, an MPU-6050 and an HMC5883L; every line it prints checked against the datasheets.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "devices/hcsr04.h"
#include "firmware_run.hpp"

using namespace sear::test;

namespace {

std::string project(const std::string& firmware, double duration_s = 1.0) {
  const std::string mcu = "    <mcu name=\"main\">\n      <firmware executable=\"" + firmware +
                          "\"/>\n      <hcsr04 name=\"sonar\" trig=\"24\" echo=\"2\" pos=\"0.15 0 0.05\"/>\n"
                          "      <mpu6050 name=\"imu\" pos=\"0 0 0.05\"/>\n"
                          "      <hmc5883l name=\"compass\" pos=\"0 0 0.1\"/>\n    </mcu>\n";
  const std::string wall = "    <wall name=\"target\" from=\"1.2 -2\" to=\"1.2 2\" height=\"0.5\" thickness=\"0.1\"/>\n";
  return rover_project(mcu, wall, duration_s);
}

class LayerProbe : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    run_ = new SearRun(run_sear(*dir_, project(LAYER_PROBE)));
  }
  static void TearDownTestSuite() {
    delete run_;
    delete dir_;
  }
  static std::vector<std::string> lines() { return lines_of(run_->file("rover.main.console.log")); }
  static bool has(const std::string& line) {
    for (const auto& l : lines())
      if (l.find(line) != std::string::npos && l.size() - l.find(line) == line.size()) return true;
    return false;
  }
  static TempDir* dir_;
  static SearRun* run_;
};
TempDir* LayerProbe::dir_ = nullptr;
SearRun* LayerProbe::run_ = nullptr;

TEST_F(LayerProbe, RunsToTheEnd) { ASSERT_EQ(run_->exit_code, 0) << run_->err << run_->file("rover.main.console.log"); }

// Debian's Print and WString, compiled unchanged: bases, float digits, String concatenation and
// replace(); the Mega's pin numbers and interrupt numbering (pins 2, 3, 21, 18 are 0, 1, 2, 5).
TEST_F(LayerProbe, PrintStringAndTheMegasPins) {
  EXPECT_TRUE(has("FF 11111111 3.142")) << run_->file("rover.main.console.log");
  EXPECT_TRUE(has("led 13 A0 54 int 0125"));
}

// endTransmission(false) keeps the bus (0) and requestFrom reads after a repeated start: the
// MPU-6050 answers WHO_AM_I with 0x68, the HMC5883L its identification "H43"; an empty address
// is endTransmission's code 2 (address NACK).
TEST_F(LayerProbe, WireWithRepeatedStartAndItsReturnCodes) {
  EXPECT_TRUE(has("imu 0 1 68"));
  EXPECT_TRUE(has("compass H43"));
  EXPECT_TRUE(has("absent 2"));
}

// Debian's EEPROM library on the HAL's 4 KiB: erased cells read 255, put/get round-trips.
TEST_F(LayerProbe, DebiansEepromLibraryOnTheHal) {
  EXPECT_TRUE(has("eeprom length 4096"));
  EXPECT_TRUE(has("eeprom erased 255"));
  EXPECT_TRUE(has("eeprom float 2.50"));
}

// Servo.write(90) between the library's 544 and 2400 us: map(90, 0, 180, 544, 2400) = 1472.
TEST_F(LayerProbe, ServoAngleToPulse) { EXPECT_TRUE(has("servo us 1472")); }

// pulseIn against the HC-SR04's echo: 58 us per cm of the 1.00 m to the wall, within the model's
// 3-sigma range noise (3 mm = 17.4 us) and the rounding to whole microseconds; the CHANGE
// interrupt on the same pin sees both edges of every echo.
TEST_F(LayerProbe, PulseInTimesTheEcho) {
  int echoes = 0;
  unsigned long previous_edges = 0;
  for (const auto& line : lines()) {
    unsigned long v = 0;
    if (std::sscanf(line.c_str(), "%*s echo us %lu", &v) == 1) {
      ++echoes;
      EXPECT_NEAR(static_cast<double>(v), 5800.0, 17.4 + 1) << line;
    }
    if (std::sscanf(line.c_str(), "%*s edges %lu", &v) == 1) {
      EXPECT_EQ(v, previous_edges + 2) << line;
      previous_edges = v;
    }
  }
  EXPECT_GE(echoes, 10);
}

// Determinism: the same sketch, seed and scenario give the same console bytes.
TEST_F(LayerProbe, SameSeedSameBytes) {
  TempDir again;
  const SearRun second = run_sear(again, project(LAYER_PROBE));
  ASSERT_EQ(second.exit_code, 0);
  EXPECT_EQ(second.file("rover.main.console.log"), run_->file("rover.main.console.log"));
}

// The same sketch folder named in the project (<firmware sketch="...">): `sear` preprocesses and
// builds it itself, and it prints the same bytes as the build CMake made.
TEST_F(LayerProbe, ASketchFolderInTheProjectRunsAsTheSameFirmware) {
  TempDir again;
  std::string p = project(LAYER_PROBE);
  const std::string exe = std::string("executable=\"") + LAYER_PROBE + "\"";
  p.replace(p.find(exe), exe.size(), std::string("sketch=\"") + LAYER_PROBE_SKETCH + "/\"");
  const SearRun run = run_sear(again, p);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.file("rover.main.console.log"), run_->file("rover.main.console.log"));
}

}  // namespace
