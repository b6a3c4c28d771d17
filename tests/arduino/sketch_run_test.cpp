// Sketches run by `sear` from their folders: the HC-SR04 example reads the wall's distance, and what
// the layer cannot model stops the MCU with a message naming the call.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "firmware_run.hpp"

using namespace sear::test;

namespace {

// `sear run` on a project file where it lies (its relative paths stay valid).
SearRun run_project(const TempDir& dir, const std::string& project) {
  const auto out = dir.path() / "out";
  const std::string cmd = std::string(SEAR_BINARY) + " run " + project + " -o " + out.string() + " >" +
                          (dir.path() / "stdout").string() + " 2>" + (dir.path() / "stderr").string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_file(dir.path() / "stdout"),
          read_file(dir.path() / "stderr"), out};
}

// The wall's face is 1.00 m from the sensor: Arduino's ping arithmetic (us / 29 / 2, truncated)
// gives 99 or 100 cm within the model's 3 mm noise; every line within a centimetre of 100.
TEST(SonarSketch, ReportsTheWallWithinACentimetre) {
  TempDir dir;
  const SearRun run = run_project(dir, std::string(SEAR_EXAMPLES_DIR) + "/arduino/sonar_sketch/project.xml");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  int readings = 0;
  for (const auto& line : lines_of(run.file("rover.main.console.log"))) {
    long us = 0, cm = 0;
    if (std::sscanf(line.c_str(), "%*s %ld us, %ld cm", &us, &cm) != 2) continue;
    ++readings;
    EXPECT_NEAR(static_cast<double>(cm), 100.0, 1.0) << line;
    EXPECT_NEAR(static_cast<double>(us), 5800.0, 17.4 + 1) << line;  // 3-sigma noise, rounding
  }
  EXPECT_GE(readings, 15);  // one per ~106 ms over 2 s
}

// As on the Mega, the first Servo takes Timer5: PWM on pin 45 afterwards stops the MCU, and the
// run's summary names the call; what the sketch printed before it still went out.
TEST(RefusedSketch, AnalogWriteOnTimer5AfterAServoStopsTheMcuWithTheCallNamed) {
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project("    <mcu name=\"main\">\n      <firmware sketch=\"" +
                                                  std::string(REFUSED_PWM_SKETCH) + "\"/>\n    </mcu>\n",
                                                  "", 0.2));
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.out.find("analogWrite() on pin 44, 45 or 46: the first Servo took Timer5"), std::string::npos)
      << run.out;
  EXPECT_EQ(run.out.find("not reached"), std::string::npos);
}

}  // namespace
