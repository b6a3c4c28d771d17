// Mistakes in a robot's <mcu> wiring are reported with the file, the line and what was expected,
// all of them at once: unknown motors, pins and channels used twice or out of range, missing
// firmware, and actuators that both a script and an MCU would drive.
#include <gtest/gtest.h>

#include <algorithm>

#include "scene/loader_parts.hpp"
#include "scene/project_loader.hpp"
#include "temp_dir.hpp"

namespace sear {
namespace {

using sear::test::TempDir;

// A rover with one MCU; `mcu_body` is the inside of its <mcu> element.
std::string project_with(const std::string& mcu_body, const std::string& script = "") {
  return std::string("<project name=\"wiring\">\n  <world step=\"0.001\"/>\n  <robot file=\"") + SEAR_ASSET_DIR +
         "/robots/rover.xml\">\n" + script + "    <mcu name=\"main\">\n" + mcu_body + "    </mcu>\n  </robot>\n</project>\n";
}

const std::string kFirmware = "      <firmware sources=\"main.c\"/>\n";

struct Loaded {
  std::string path;
  Diagnostics diagnostics;
  std::optional<ProjectDesc> project;
};

Loaded load(const TempDir& dir, const std::string& xml) {
  dir.write("main.c", "int main(void) { return 0; }\n");
  Loaded out;
  out.path = dir.write("project.xml", xml);
  out.project = load_project(out.path, out.diagnostics);
  return out;
}

// Some diagnostic is on `line` of the project and says every one of `parts`.
::testing::AssertionResult says(const Loaded& l, int line, std::initializer_list<const char*> parts) {
  for (const auto& d : l.diagnostics.all()) {
    if (d.line == line && d.file == l.path &&
        std::all_of(parts.begin(), parts.end(), [&](const char* p) { return d.message.find(p) != std::string::npos; }))
      return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "nothing on line " << line << " says that; got:\n" << l.diagnostics.joined();
}

TEST(McuWiringErrors, AValidMcuLoads) {
  TempDir dir;
  const Loaded l = load(dir, project_with(kFirmware + R"(      <gp2d12 name="ir" adc="0" pos="0.15 0 0.02"/>
      <bump name="bumper" pin="2" pos="0.14 0 0"/>
      <motor name="left" pwm="3" dir="12" brake="9"/>
      <uart port="1" loopback="true"/>
)"));
  ASSERT_TRUE(l.diagnostics.ok()) << l.diagnostics.joined();
  const McuDesc& mcu = l.project->robots[0].mcus[0];
  EXPECT_EQ(mcu.firmware_sources.size(), 1u);
  EXPECT_DOUBLE_EQ(mcu.clock_hz, 16e6);
  EXPECT_EQ(mcu.devices[0].wire("adc"), 0);
  EXPECT_TRUE(mcu.uarts[0].loopback);
}

TEST(McuWiringErrors, EveryWiringMistakeIsReportedWhereItIs) {
  TempDir dir;
  const Loaded l = load(dir, project_with(kFirmware + R"(      <gp2d12 name="ir" adc="16" pos="0.15 0 0.02"/>
      <gp2d15 name="front" pin="22" switch_distance="0.3"/>
      <bump name="bumper" pin="22"/>
      <motor name="lfet" pwm="3" dir="12"/>
      <motor name="right" pwm="70" dir="13"/>
      <servo name="steer" pin="11"/>
      <uart port="1"/>
      <uart port="1"/>
      <laser name="x"/>
)"));
  EXPECT_FALSE(l.project.has_value());
  EXPECT_TRUE(says(l, 6, {"'adc'", "0..15"}));
  EXPECT_TRUE(says(l, 7, {"switch_distance", "0.21..0.27 m"}));
  EXPECT_TRUE(says(l, 8, {"pin 22 is wired to both 'front' and 'bumper'"}));
  EXPECT_TRUE(says(l, 9, {"unknown motor 'lfet'", "did you mean 'left'"}));
  EXPECT_TRUE(says(l, 10, {"'pwm'", "0..69"}));
  EXPECT_TRUE(says(l, 11, {"unknown servo 'steer'"}));
  EXPECT_TRUE(says(l, 13, {"UART port 1 is wired to both"}));
  EXPECT_TRUE(says(l, 14, {"laser"}));
}

// Issue 22: a motor's speed is PWM duty, and pwm_write() on a pin with no timer output stops the
// firmware at its first drive; the loader says so before the run, once, where the motor is wired.
TEST(McuWiringErrors, AMotorsPwmPinMustHavePwm) {
  TempDir dir;
  const Loaded l = load(dir, project_with(kFirmware + R"(      <motor name="left" pwm="30" dir="12"/>
      <motor name="right" pwm="46" dir="13"/>
)"));
  EXPECT_FALSE(l.project.has_value());
  EXPECT_TRUE(says(l, 6, {"motor 'left' has pwm=\"30\", a pin with no PWM on the ATmega2560",
                          "its PWM pins are 2..13 and 44..46"}));
  EXPECT_EQ(l.diagnostics.count(), 1u) << l.diagnostics.joined();  // pin 46 (timer 5's OC5A) has PWM
}

// Issue 22: a sensor at pos="15 0 2" on a 30 cm rover loads, but looks at the world from 15 m
// away: a warning where it is written, with the distance and the robot's own reach.
TEST(McuWiringErrors, ASensorFarOutsideItsRobotIsWarnedOf) {
  TempDir dir;
  const Loaded l = load(dir, project_with(kFirmware + R"(      <gp2d12 name="ir" adc="0" pos="15 0 2"/>
      <gp2d12 name="mast" adc="1" pos="0.1 0 0.8"/>
)"));
  ASSERT_TRUE(l.diagnostics.ok()) << l.diagnostics.joined();  // a warning: the run goes ahead
  ASSERT_EQ(l.diagnostics.warnings().size(), 1u) << l.diagnostics.warnings_joined();
  const Diagnostic& w = l.diagnostics.warnings()[0];
  EXPECT_EQ(w.file, l.path);
  EXPECT_EQ(w.line, 6);
  // |(15, 0, 2)| = 15.13 m. The rover's reach is its chassis' half-diagonal, 0.5 * |(0.30, 0.18,
  // 0.06)| = 0.1775 m (its wheels reach |(0.04, 0.11, -0.01)| + 0.045 = 0.162 m): the mast at
  // 0.806 m stays within 5 times that (0.888 m).
  EXPECT_EQ(w.str(), l.path + ":6: warning: robot 'rover': <gp2d12> 'ir' at pos=\"15 0 2\" is 15.1 m from the "
                              "robot's origin, while the robot itself reaches 0.177 m from it: 'pos' is in metres "
                              "(centimetres written as metres?)");
  EXPECT_NEAR(robot_reach_m(l.project->robots[0]), 0.17748, 1e-5);  // 0.5 * sqrt(0.126), to the 5th digit
}

TEST(McuWiringErrors, FirmwareMustBeNamedAndExist) {
  TempDir dir;
  EXPECT_TRUE(says(load(dir, project_with("")), 4, {"<mcu> needs a <firmware>"}));
  EXPECT_TRUE(says(load(dir, project_with("      <firmware sources=\"nowhere.c\"/>\n")), 5,
                   {"firmware source 'nowhere.c' not found"}));
  EXPECT_TRUE(says(load(dir, project_with("      <firmware executable=\"nowhere\"/>\n")), 5,
                   {"firmware executable 'nowhere' not found"}));
  EXPECT_TRUE(says(load(dir, project_with("      <firmware/>\n")), 5, {"either 'executable'", "or 'sources'"}));
}

TEST(McuWiringErrors, AMotorCannotBeDrivenByBothAScriptAndAnMcu) {
  TempDir dir;
  const Loaded l = load(dir, project_with(kFirmware + "      <motor name=\"left\" pwm=\"3\" dir=\"12\"/>\n",
                                          "    <script><motor t=\"0\" name=\"left\" duty=\"1\"/></script>\n"));
  EXPECT_TRUE(says(l, 7, {"'left' is driven by both the robot's <script> and mcu 'main'"}));
}

TEST(McuWiringErrors, AReceivedCaptureMustBeOneThatSearWrites) {
  TempDir dir;
  const std::string capture = dir.write("bad.log", "# a capture\n0.001 tx 41\n0.002 sent 42\n0.003 tx 4g\n");
  const Loaded l = load(dir, project_with(kFirmware + "      <uart port=\"1\" receive=\"bad.log\"/>\n"));
  const auto at = [&](int line, const char* part) {
    return std::any_of(l.diagnostics.all().begin(), l.diagnostics.all().end(), [&](const Diagnostic& d) {
      return d.file == capture && d.line == line && d.message.find(part) != std::string::npos;
    });
  };
  EXPECT_TRUE(at(3, "expected 'time_s direction value'")) << l.diagnostics.joined();
  EXPECT_TRUE(at(4, "'4g' is not a byte in hex")) << l.diagnostics.joined();
  EXPECT_TRUE(says(load(dir, project_with(kFirmware + "      <uart port=\"1\" loopback=\"true\" receive=\"bad.log\"/>\n")), 6,
                   {"loopback", "not both"}));
  EXPECT_TRUE(says(load(dir, project_with(kFirmware + "      <uart port=\"1\" receive=\"none.log\"/>\n")), 6,
                   {"UART capture 'none.log' not found"}));
}

TEST(McuWiringErrors, AnMcuTakesAtMost32Sensors) {
  std::string bumps;
  for (int pin = 22; pin < 22 + 33; ++pin)
    bumps += "      <bump name=\"b" + std::to_string(pin) + "\" pin=\"" + std::to_string(pin) + "\"/>\n";
  TempDir dir;
  EXPECT_TRUE(says(load(dir, project_with(kFirmware + bumps)), 4, {"mcu 'main' has 33 sensors served in its process; an MCU takes at most 32"}));
}

}  // namespace
}  // namespace sear
