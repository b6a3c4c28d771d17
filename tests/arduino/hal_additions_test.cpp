// What the HAL gained for the Arduino layer (issue 19), through `sear run` on the bundled rover
// standing 1.00 m from a wall: pulse measurement, I2C write-then-read, the UART's transmit space,
// the 2.56 V reference, level interrupts, servo pulses on any pin and the EEPROM.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "devices/maxbotix_lv_ez.h"
#include "firmware_run.hpp"

using namespace sear::test;

namespace {

// The MaxBotix 0.15 m ahead of the rover's centre, the wall's face at 1.15 m: 1.00 m = 39.37 in,
// which the part (noise off) reads as 39 whole inches.
constexpr int kInches = 39;

std::string project() {
  const std::string mcu = std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + HAL_ADDITIONS_PROBE +
                          "\"/>\n      <maxbotix_lv_ez name=\"mb\" adc=\"2\" pw=\"62\" noise=\"0\" pos=\"0.15 0 0.08\"/>\n"
                          "      <hmc5883l name=\"compass\" pos=\"0 0 0.1\"/>\n    </mcu>\n";
  const std::string wall = "    <wall name=\"target\" from=\"1.2 -2\" to=\"1.2 2\" height=\"0.5\" thickness=\"0.1\"/>\n";
  return rover_project(mcu, wall, 1.2);
}

// The console log's line (after its time stamp) that starts with `head`.
std::string line_starting(const std::string& log, const std::string& head) {
  for (const auto& stamped : lines_of(log)) {
    const std::string line = stamped.substr(stamped.find(' ') + 1);
    if (line.rfind(head, 0) == 0) return line;
  }
  return "";
}

class HalAdditions : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    run_ = new SearRun(run_sear(*dir_, project()));
  }
  static void TearDownTestSuite() {
    delete run_;
    delete dir_;
  }
  static std::string log() { return run_->file("rover.main.console.log"); }
  static TempDir* dir_;
  static SearRun* run_;
};
TempDir* HalAdditions::dir_ = nullptr;
SearRun* HalAdditions::run_ = nullptr;

TEST_F(HalAdditions, RunsToTheEnd) { ASSERT_EQ(run_->exit_code, 0) << run_->err; }

// pulse_in times the model's own PW edges: 147 us per inch, to the microsecond (the HAL rounds the
// nanosecond width to the nearest microsecond, and the model's width is a whole number of them).
TEST_F(HalAdditions, PulseInIsExactAgainstTheModelledEdges) {
  int lines = 0;
  for (const auto& stamped : lines_of(log())) {
    const std::string line = stamped.substr(stamped.find(' ') + 1);
    unsigned long pw = 0, none = 99;
    unsigned avcc = 0, r256 = 0;
    if (std::sscanf(line.c_str(), "pw %lu us timeout %lu adc %u %u", &pw, &none, &avcc, &r256) != 4) continue;
    ++lines;
    EXPECT_EQ(pw, static_cast<unsigned long>(kInches * MAXBOTIX_PW_NS_PER_INCH / 1000)) << line;
    EXPECT_EQ(none, 0u) << line;  // 100 us is far shorter than the 49 ms cycle: a timeout
  }
  EXPECT_EQ(lines, 5);
}

// AN gives Vcc/512 per inch; the ADC's code is Vin * 1024 / Vref, truncated: against AVCC (5 V)
// and the internal 2.56 V reference.
TEST_F(HalAdditions, TheTwoPointFiveSixVoltReferenceScalesTheCode) {
  const double vin = 5.0 / MAXBOTIX_AN_STEPS_PER_VCC * kInches;
  unsigned long pw = 0, none = 0;
  unsigned avcc = 0, r256 = 0;
  const std::string line = line_starting(log(), "pw ");
  ASSERT_EQ(std::sscanf(line.c_str(), "pw %lu us timeout %lu adc %u %u", &pw, &none, &avcc, &r256), 4) << log();
  EXPECT_EQ(avcc, static_cast<unsigned>(std::floor(vin * 1024 / 5.0)));
  EXPECT_EQ(r256, static_cast<unsigned>(std::floor(vin * 1024 / 2.56)));
}

// Write-then-read with a repeated start and a write without stop followed by a read both reach
// the HMC5883L's identification registers ("H43"); an empty address is an address NACK (-1).
TEST_F(HalAdditions, I2cWriteReadAndWriteWithoutStop) {
  EXPECT_EQ(line_starting(log(), "i2c "), "i2c 0 H43 0 0 H43 -1");
}

// Idle: all 64 places free. Ten bytes at once: the first two go to the shift and data registers,
// eight wait in the ring (64 - 8 = 56). After uart_flush: 64 again.
TEST_F(HalAdditions, TransmitSpaceFollowsTheBytesOnTheWire) {
  EXPECT_EQ(line_starting(log(), "tx space "), "tx space 64 56 64");
}

// A level interrupt on a pin held LOW runs at once and again after each round, until its handler
// drives the pin HIGH on the fifth.
TEST_F(HalAdditions, ALevelInterruptRepeatsWhileThePinIsLow) {
  EXPECT_EQ(line_starting(log(), "level rounds "), "level rounds 5");
}

// The EEPROM starts erased (0xFF), reads back what was written, and each access waits for the write
// before it: the boot counter's write is still programming when the timing starts, then four
// writes and a read cost five programming times (5 x 3.3 ms), and at most ten HAL calls (3.125 us
// each at the default cost) more.
TEST_F(HalAdditions, EepromStartsErasedAndWritesTakeTheirProgrammingTime) {
  unsigned boots = 0, erased = 0, back = 0;
  unsigned long us = 0;
  const std::string line = line_starting(log(), "eeprom ");
  ASSERT_EQ(std::sscanf(line.c_str(), "eeprom boots %u erased %u back %u us %lu", &boots, &erased, &back, &us), 4);
  EXPECT_EQ(boots, 1u);
  EXPECT_EQ(erased, 0xFFu);
  EXPECT_EQ(back, 103u);
  EXPECT_GE(us, 5 * 3300u - 4u);  // t0 is read a call's cost after the boot counter's write began
  EXPECT_LE(us, 5 * 3300u + 10 * 4u);
}

// With SEAR_EEPROM_FILE set the contents outlive the run: the boot counter counts two runs, and the
// file holds the whole erased chip besides. The simulator gives a firmware a fixed environment, so
// the variable is set by a wrapper script the project names as the executable.
TEST(HalEeprom, PersistsInTheFileNamedAcrossRuns) {
  TempDir dir;
  const std::string file = (dir.path() / "main.eeprom").string();
  const std::string wrapper = (dir.path() / "probe.sh").string();
  std::ofstream(wrapper) << "#!/bin/sh\nSEAR_EEPROM_FILE=" << file << " exec " << HAL_ADDITIONS_PROBE << "\n";
  std::filesystem::permissions(wrapper, std::filesystem::perms::owner_all);
  std::string p = project();
  p.replace(p.find(HAL_ADDITIONS_PROBE), std::string(HAL_ADDITIONS_PROBE).size(), wrapper);
  const SearRun first = run_sear(dir, p, "--duration 0.1");
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_EQ(line_starting(first.file("rover.main.console.log"), "eeprom boots ").substr(0, 15), "eeprom boots 1 ");
  const SearRun second = run_sear(dir, p, "--duration 0.1");
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(line_starting(second.file("rover.main.console.log"), "eeprom boots ").substr(0, 15), "eeprom boots 2 ");
  const std::string cells = read_file(file);
  ASSERT_EQ(cells.size(), 4096u);
  EXPECT_EQ(static_cast<unsigned char>(cells[0]), 2);
  EXPECT_EQ(static_cast<unsigned char>(cells[103]), 103);
  EXPECT_EQ(static_cast<unsigned char>(cells[4095]), 0xFF);
}

}  // namespace
