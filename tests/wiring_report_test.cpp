// A run whose wiring does not match its firmware completes as it would on the bench, but says so:
// each device input the firmware never drove, read or set up, each write that only moved a
// pull-up, each pin driven with nothing on it, and a printf() that went to the host log only;
// a HAL call before hal_init() that the board could not do stops the MCU with a report naming it.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "firmware_run.hpp"

namespace sear::test {
namespace {

// The probe (firmware/wiring_probe.c) pulses TRIG on 24, times ECHO on 23, writes pin 30 HIGH as
// an input and prints with printf(); `devices` is the wiring the project gives it.
std::string project(const char* firmware, const std::string& devices) {
  return rover_project(std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + firmware + "\"/>\n" +
                           devices + "    </mcu>\n",
                       "    <wall name=\"target\" from=\"1.2 -2\" to=\"1.2 2\" height=\"0.5\" thickness=\"0.1\"/>\n",
                       0.5);
}

std::size_t count(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

// TRIG wired to 22 while the firmware pulses 24: the classic "reads 400 forever".
const std::string kMiswired =
    "      <hcsr04 name=\"sonar\" trig=\"22\" echo=\"23\" pos=\"0.15 0 0.05\"/>\n"
    "      <gp2d12 name=\"ir\" adc=\"3\" pos=\"0.15 0 0.02\"/>\n"
    "      <ublox_neo6m name=\"gps\" uart=\"1\" pos=\"0 0 0.1\"/>\n"
    "      <hmc5883l name=\"compass\" pos=\"0 0 0.1\"/>\n"
    "      <mpu6000 name=\"imu\" cs=\"53\" pos=\"0 0 0.05\"/>\n";

TEST(WiringReport, EveryInputTheFirmwareNeverReachedIsNamedWithItsDevicePinAndMcu) {
  TempDir dir;
  const SearRun run = run_sear(dir, project(WIRING_PROBE, kMiswired));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // The symptom the report explains: no pulse on 22, so no echo, and pulse_in times out (0).
  EXPECT_NE(run.file("rover.main.console.log").find("echo 0 us "), std::string::npos);

  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_EQ(summary["status"], "completed");
  struct Expected {
    const char* kind;
    const char* device;
    int pin;
    const char* says;
  };
  // In the report's order: devices as wired, then pins by number. ECHO (23) was read: no note.
  const Expected expected[] = {
      {"unused wiring", "sonar", 22, "mcu rover.main: hcsr04 'sonar': its trig pin 22 was never set as an OUTPUT"},
      {"unused wiring", "ir", 3, "mcu rover.main: gp2d12 'ir': its output on ADC channel 3 (pin A3) was never read"},
      {"unused wiring", "gps", 1, "mcu rover.main: ublox_neo6m 'gps': it is on uart1, which the firmware never began"},
      {"unused wiring", "compass", 0x1E, "mcu rover.main: hmc5883l 'compass': at I2C address 30 (0x1E) it was never addressed"},
      {"unused wiring", "imu", 53, "mcu rover.main: mpu6000 'imu': its cs pin 53 never selected it for an SPI transfer"},
      // Four HAL calls before it at 50 cycles each on a 16 MHz chip: 4 * 3.125 us.
      {"write to an input", "", 30,
       "mcu rover.main: a digital_write of HIGH to pin 30 at 0.000012500 s, a pin never set as an OUTPUT, only turned "
       "its pull-up on"},
      {"unwired output", "", 24, "mcu rover.main: the firmware drove pin 24 as an output, and nothing in the project is "
                                 "wired to it (fine for an LED"},
  };
  ASSERT_EQ(summary["wiring"].size(), std::size(expected)) << summary["wiring"].dump(2);
  const std::string text = run.file("summary.txt");
  for (std::size_t i = 0; i < std::size(expected); ++i) {
    const auto& note = summary["wiring"][i];
    const Expected& e = expected[i];
    EXPECT_EQ(note["mcu"], "rover.main");
    EXPECT_EQ(note["kind"], e.kind) << i;
    EXPECT_EQ(note["device"], e.device) << i;
    EXPECT_EQ(note["pin"], e.pin) << i;
    const std::string line = note["text"];
    EXPECT_EQ(line.rfind(e.says, 0), 0U) << line;
    // Once in each: the summary's text and standard error, at the end of the run.
    EXPECT_EQ(count(text, line + "\n"), 1U) << line;
    EXPECT_EQ(count(run.err, line + "\n"), 1U) << line << "\n" << run.err;
  }
}

TEST(WiringReport, WiringThatMatchesTheFirmwareGivesNoUnusedInput) {
  TempDir dir;
  const SearRun run = run_sear(dir, project(WIRING_PROBE,
                                            "      <hcsr04 name=\"sonar\" trig=\"24\" echo=\"23\" pos=\"0.15 0 0.05\"/>\n"
                                            "      <gp2d12 name=\"ir\" adc=\"0\" pos=\"0.15 0 0.02\"/>\n"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  // Only what the probe always does is left: the pull-up write, and SS (53) with nothing on it.
  ASSERT_EQ(summary["wiring"].size(), 2U) << summary["wiring"].dump(2);
  EXPECT_EQ(summary["wiring"][0]["kind"], "write to an input");
  EXPECT_EQ(summary["wiring"][1]["kind"], "unwired output");
  EXPECT_EQ(summary["wiring"][1]["pin"], 53);
  EXPECT_EQ(run.err.find("sear: wiring:"), std::string::npos) << run.err;
  // And the sonar works: the wall 1.15 m ahead of the sensor's 0.15 m mount, 58 us per cm,
  // within 10 % for the rover's creep and the echo's noise.
  unsigned long width = 0;
  for (const auto& line : lines_of(run.file("rover.main.console.log")))
    if (std::sscanf(line.c_str(), "%*s echo %lu us", &width) == 1 && width) break;
  EXPECT_NEAR(static_cast<double>(width), 58.0 * 100, 580.0);
}

TEST(WiringReport, APrintfIsSaidOnceOnTheConsoleWithWhereItWent) {
  TempDir dir;
  const SearRun run = run_sear(dir, project(WIRING_PROBE, kMiswired));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.file("rover.main.host.log").find("printf reaches the host log only\n"), std::string::npos);
  // Printed in the first 1 ms quantum; told at its end.
  const std::string note = "sear: mcu rover.main wrote to its standard output (printf, puts) by sim time 0.001 s: that "
                           "goes to " + run.dir.string() + "/rover.main.host.log only; uart_print(0, ...) on its "
                           "console UART shows text on this console\n";
  EXPECT_EQ(count(run.err, note), 1U) << run.err;
}

TEST(WiringReport, APrintfAfterTheFirstTurnIsToldAtTheNextTenMillisecondMark) {
  TempDir dir;
  const SearRun run = run_sear(dir, project(LATE_PRINT_PROBE, kMiswired));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // Printed after delay_ms(25), in the turn [25, 26) ms. The stdout is looked at after the first
  // turn, then once every 10 ms of sim time (a system call each), so the turn that ends at 30 ms
  // sees it.
  EXPECT_EQ(count(run.err, "wrote to its standard output (printf, puts) by sim time 0.030 s"), 1U) << run.err;
}

TEST(WiringReport, AHalCallBeforeHalInitStopsTheMcuNamingTheCall) {
  TempDir dir;
  const SearRun run = run_sear(dir, project(EARLY_CALL_PROBE, kMiswired));
  EXPECT_EQ(run.exit_code, 3) << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  ASSERT_EQ(summary["mcu_stops"].size(), 1U);
  const auto& stop = summary["mcu_stops"][0];
  EXPECT_EQ(stop["kind"], "refused");
  EXPECT_EQ(stop["last_hal_call"], "millis");
  // After pin_mode and digital_write, which the board does before hal_init() too: two calls of
  // 50 cycles at 16 MHz.
  EXPECT_DOUBLE_EQ(stop["sim_time_s"].get<double>(), 2 * 3.125e-6);
  EXPECT_EQ(std::string(stop["detail"]).rfind("millis() called before hal_init()", 0), 0U) << stop["detail"];
  EXPECT_NE(run.err.find("millis() called before hal_init()"), std::string::npos) << run.err;
  EXPECT_EQ(summary["wiring"].size(), 0U);  // a stopped MCU has its report already
}

}  // namespace
}  // namespace sear::test
