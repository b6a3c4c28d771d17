// Lockstep semantics seen from firmware written for the tests: exact edge times, a timer that fires
// exactly 1000 times a second, busy-waits that end, UART bytes spaced by the baud rate, and two
// copies of one firmware that keep their own globals.
#include <gtest/gtest.h>

#include <cstdint>
#include <algorithm>
#include <cstdio>
#include <map>
#include <regex>

#include "firmware_run.hpp"

namespace sear::test {
namespace {

// Edge times per VCD identifier, after each pin's first value (the level it starts at).
std::map<char, std::vector<std::int64_t>> vcd_edges(const std::string& vcd) {
  std::map<char, std::vector<std::int64_t>> edges;
  std::map<char, char> level;
  std::int64_t t = 0;
  bool dumping = false;
  for (const auto& line : lines_of(vcd)) {
    if (line == "$enddefinitions $end") dumping = true;
    if (!dumping || line.empty() || line[0] == '$') continue;
    if (line[0] == '#') {
      t = std::stoll(line.substr(1));
    } else if (line.size() == 2) {
      const char id = line[1], value = line[0];
      if (level.count(id) && level[id] != 'z' && value != 'z' && level[id] != value) edges[id].push_back(t);
      level[id] = value;
    }
  }
  return edges;
}

const char kPin12 = '!' + 12;
const char kPin13 = '!' + 13;

// The timer probe with HAL calls that cost nothing, so that only delays and the timer move time.
std::string timer_probe_project(double duration_s) {
  return rover_project(std::string(R"(    <mcu name="timer" hal_call_cycles="0">
      <firmware executable=")") + TIMER_PROBE + R"("/>
    </mcu>
)", "", duration_s);
}

TEST(Lockstep, EdgesFromDelaysAndTimerInterruptsFallOnExactMultiplesOf10ms) {
  TempDir dir;
  const auto run = run_sear(dir, timer_probe_project(2.05));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto edges = vcd_edges(run.file("rover.timer.pins.vcd"));
  for (const char pin : {kPin12, kPin13}) {
    ASSERT_TRUE(edges.count(pin)) << "pin " << int(pin - '!');
    const auto& e = edges.at(pin);
    // 2.05 s of 10 ms half-periods; the run stops just before the edge at 2.050 s.
    ASSERT_EQ(e.size(), 204u) << "pin " << int(pin - '!');
    for (std::size_t k = 0; k < e.size(); ++k) EXPECT_EQ(e[k], static_cast<std::int64_t>(k + 1) * 10'000'000);
  }
}

TEST(Lockstep, A1kHzTimerFiresExactly1000TimesPerSimulatedSecond) {
  TempDir dir;
  const auto run = run_sear(dir, timer_probe_project(3.05));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string console = run.file("rover.timer.console.log");
  // Counted at each whole second, after the tick due at that very moment; the console stamps a
  // line when its last byte has left the wire, 11 bytes at 115200 baud later.
  const double line_s = 11 * 10 / 115200.0;
  for (int s = 1; s <= 3; ++s) {
    char expected[64];
    std::snprintf(expected, sizeof expected, "%d.%09.0f ticks %d\n", s, line_s * 1e9, 1000 * s);
    EXPECT_NE(console.find(expected), std::string::npos) << "no '" << expected << "' in\n" << console;
  }
}

TEST(Lockstep, PinsAndInterruptsBehaveAsOnTheChip) {
  TempDir dir;
  const auto run = run_sear(dir, rover_project(std::string(R"(    <mcu name="main">
      <firmware executable=")") + GPIO_PROBE + R"("/>
      <motor name="left" pwm="3" dir="12"/>
    </mcu>
)", "", 0.5));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // The pull-up reads HIGH; INPUT_PULLUP then OUTPUT drives HIGH; INPUT then OUTPUT drives LOW;
  // a 1 kHz handler that disables interrupts still runs every millisecond for 100 ms.
  EXPECT_NE(run.file("rover.main.console.log").find("a=1 b=1 c=0 ticks=100"), std::string::npos)
      << run.file("rover.main.console.log");
  // pwm_write(3, 255) drives the left motor at full duty, forward.
  const auto rows = lines_of(run.file("trace_rover.csv"));
  const auto header = rows.front();
  const auto column = std::count(header.begin(), header.begin() + static_cast<long>(header.find("motor_left_duty")), ',');
  std::istringstream last(rows.back());
  std::string cell;
  for (long i = 0; i <= column; ++i) std::getline(last, cell, ',');
  EXPECT_DOUBLE_EQ(std::stod(cell), 1.0) << header << "\n" << rows.back();
}

TEST(Lockstep, LoopsWaitingForAnInterruptWithoutHalCallsEndWhenItFires) {
  // The rover drives into a wall on a script; its bump switch closes there.
  TempDir dir;
  const auto run = run_sear(dir, rover_project(std::string(R"(    <script>
      <motor t="0" name="left" duty="0.5"/>
      <motor t="0" name="right" duty="0.5"/>
    </script>
    <mcu name="main">
      <firmware executable=")") + WAIT_PROBE + R"("/>
      <bump name="bumper" pin="2" pos="0.14 0 -0.01" width="0.18" reach="0.02"/>
    </mcu>
)", "    <wall name=\"w\" from=\"0.6 -1\" to=\"0.6 1\" height=\"0.4\"/>\n", 3.0));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string console = run.file("rover.main.console.log");
  // Each wait ends at the tick that set the flag: the timer started at 6.25 us, after two calls.
  EXPECT_NE(console.find("waits ended at 100006 200006 300006 400006 500006 us"), std::string::npos) << console;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(console, m, std::regex("bumped at (\\d+) us"))) << console;
  // The wall's face is 0.53 m ahead of the lever's reach at about 0.35 m/s.
  EXPECT_GT(std::stol(m[1]), 1000000);
  EXPECT_LT(std::stol(m[1]), 2500000);
  // The switch is read at the start of each 1 ms quantum, and the wait ends right then.
  EXPECT_EQ(std::stol(m[1]) % 1000, 0) << m[1];
}

class SerialProbe : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const std::string mcu = std::string(R"(      <firmware executable=")") + SERIAL_PROBE + R"("/>
      <uart port="1" loopback="true"/>
)";
    run_ = new SearRun(run_sear(*dir_, rover_project("    <mcu name=\"a\">\n" + mcu + "    </mcu>\n    <mcu name=\"b\">\n" +
                                                     mcu + "    </mcu>\n")));
  }
  static void TearDownTestSuite() {
    delete run_;
    delete dir_;
  }
  static TempDir* dir_;
  static SearRun* run_;
};
TempDir* SerialProbe::dir_ = nullptr;
SearRun* SerialProbe::run_ = nullptr;

TEST_F(SerialProbe, ABusyWaitOnTheMillisecondClockEnds) {
  ASSERT_EQ(run_->exit_code, 0) << run_->err;
  std::smatch m;
  const std::string console = run_->file("rover.a.console.log");
  ASSERT_TRUE(std::regex_search(console, m, std::regex("busy-wait ended at (\\d+) us"))) << console;
  // Each call costs 50 cycles at 16 MHz, 3.125 us. hal_init() and uart_begin() take the clock to
  // 6.25 us, the first millis() (the target, 0 + 250 ms) to 9.375 us; the loop's millis() calls
  // fall at 9.375 us + k x 3.125 us, the first at or after 250 ms exactly at it (k = 79997); then
  // micros() is called at 250.003125 ms.
  EXPECT_EQ(std::stol(m[1]), 250003);
}

TEST_F(SerialProbe, BytesAt9600BaudAre1Point0417msApartAndArriveOnTheLoopedBackRx) {
  ASSERT_EQ(run_->exit_code, 0) << run_->err;
  std::vector<double> tx, rx;
  for (const auto& line : lines_of(run_->file("rover.a.uart1.log"))) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    std::string t, dir, byte;
    in >> t >> dir >> byte;
    if (dir == "tx") tx.push_back(std::stod(t));
    if (dir == "rx") rx.push_back(std::stod(t));
  }
  ASSERT_EQ(tx.size(), 5u);
  EXPECT_EQ(tx, rx);
  // 10 bits (start, 8 data, stop) at 9600 baud = 1.041667 ms, to the nanosecond.
  for (std::size_t i = 1; i < tx.size(); ++i) EXPECT_NEAR(tx[i] - tx[i - 1], 10.0 / 9600, 1.5e-9);
  EXPECT_EQ(run_->file("rover.a.uart1.tx.bin"), "HELLO");
  EXPECT_EQ(run_->file("rover.a.uart1.rx.bin"), "HELLO");
  EXPECT_NE(run_->file("rover.a.console.log").find("rx 5: HELLO"), std::string::npos);
}

TEST(Lockstep, APortReceivesACapturedByteStreamAtItsTimes) {
  TempDir dir;
  // Another device's capture: "WORLD" sent at 115200 baud from 254 ms on, while the probe listens.
  std::string capture = "# SEAR UART capture: mcu other.main, port 2, 8N1\n";
  const char* word = "WORLD";
  for (int i = 0; i < 5; ++i) {
    char line[64];
    std::snprintf(line, sizeof line, "0.%09d tx %02x\n0.%09d rx 00\n", 254000000 + i * 86806, word[i],
                  254000000 + i * 86806);
    capture += line;
  }
  dir.write("other.uart2.log", capture);
  const auto run = run_sear(dir, rover_project(std::string(R"(    <mcu name="main">
      <firmware executable=")") + SERIAL_PROBE + R"("/>
      <uart port="1" receive="other.uart2.log"/>
    </mcu>
)"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.file("rover.main.console.log").find("rx 5: WORLD"), std::string::npos) << run.file("rover.main.console.log");
  EXPECT_EQ(run.file("rover.main.uart1.rx.bin"), "WORLD");
  // Received at the capture's times, to the nanosecond.
  EXPECT_NE(run.file("rover.main.uart1.log").find("0.254260418 rx 4c\n"), std::string::npos) << run.file("rover.main.uart1.log");
}

TEST_F(SerialProbe, TwoMcusRunningOneFirmwareKeepTheirOwnGlobals) {
  ASSERT_EQ(run_->exit_code, 0) << run_->err;
  for (const char* mcu : {"rover.a.console.log", "rover.b.console.log"}) {
    std::vector<int> counts;
    std::smatch m;
    for (const auto& line : lines_of(run_->file(mcu)))
      if (std::regex_search(line, m, std::regex(" count (\\d+)$"))) counts.push_back(std::stoi(m[1]));
    // One global shared by both would advance twice per 100 ms.
    ASSERT_GE(counts.size(), 6u) << mcu;
    for (std::size_t i = 0; i < counts.size(); ++i) EXPECT_EQ(counts[i], static_cast<int>(i) + 1) << mcu;
  }
  EXPECT_EQ(run_->file("rover.a.console.log"), run_->file("rover.b.console.log"));
}

}  // namespace
}  // namespace sear::test
