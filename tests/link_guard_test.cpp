// A firmware can break itself, never the simulator's account of it: what it scribbles over the
// shared link stops it with a report naming the field; it sees fixed addresses in every run; no
// file it makes grows past its limit; a loop that takes no simulated time is a hang; and no byte
// is stamped after the run's end or after the MCU stopped.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "firmware_run.hpp"

namespace sear::test {
namespace {

namespace fs = std::filesystem;

std::string one_mcu(const char* executable, const std::string& attributes = "") {
  return std::string("    <mcu name=\"main\"") + attributes + ">\n      <firmware executable=\"" + executable +
         "\"/>\n    </mcu>\n";
}

struct Scribble {
  const char* executable;
  const char* field;  // what the report must name
};

// Names the case in test output rather than dumping its bytes.
void PrintTo(const Scribble& s, std::ostream* os) { *os << s.field; }

class ScribbledLink : public ::testing::TestWithParam<Scribble> {};

TEST_P(ScribbledLink, StopsTheMcuWithAReportNamingTheField) {
  const Scribble s = GetParam();
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project(one_mcu(s.executable), "", 1.0), "--quiet");
  EXPECT_EQ(run.exit_code, 3) << run.err;
  const std::string report = std::string("mcu rover.main overwrote the simulator link at ") + s.field;
  EXPECT_NE(run.err.find(report), std::string::npos) << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_EQ(summary["status"], "mcu stopped");
  ASSERT_EQ(summary["mcu_stops"].size(), 1u);
  const auto& stop = summary["mcu_stops"][0];
  EXPECT_EQ(stop["kind"], "corrupted");
  // It scribbled once delay_ms(100) had ended: 100 ms after its five calls before it (3.125 us
  // each, 50 cycles at 16 MHz), and the report's time is the last clock the link checked, which
  // can only be the quantum's end before the scribble or the one it reached: 0.100 or 0.101 s.
  const double t = stop["sim_time_s"].get<double>();
  EXPECT_GE(t, 0.100);
  EXPECT_LE(t, 0.101 + 1e-9);
  EXPECT_NE(run.file("rover.main.console.log").find("scribbling"), std::string::npos);
  // The waveform's time never runs backwards, whatever the firmware wrote.
  long long last = -1;
  std::istringstream vcd(run.file("rover.main.pins.vcd"));
  for (std::string line; std::getline(vcd, line);) {
    if (line.empty() || line[0] != '#') continue;
    const long long now = std::stoll(line.substr(1));
    EXPECT_GE(now, last) << line;
    last = now;
  }
  EXPECT_LE(last, 101000000);  // nothing after it stopped
  // Only the files of this MCU and the run: nothing named from garbage.
  for (const auto& entry : fs::directory_iterator(run.dir)) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(name.rfind("rover.main.", 0) == 0 || name.rfind("summary.", 0) == 0 || name == "trace_rover.csv" ||
                name == "world.json" || name == "sensors_rover.csv" || name == ".sear-run")
        << name;
  }
}

INSTANTIATE_TEST_SUITE_P(EachField, ScribbledLink,
                         ::testing::Values(Scribble{SCRIBBLE_COUNT_PROBE, "event_count"},
                                           Scribble{SCRIBBLE_PIN_PROBE, "events[0].index"},
                                           Scribble{SCRIBBLE_CLOCK_PROBE, "clock_ns"},
                                           Scribble{SCRIBBLE_ALL_PROBE, "magic/version"},
                                           Scribble{SCRIBBLE_TIME_PROBE, "events[0].time_ns"}),
                         case_name<Scribble>);

// Addresses and uninitialised bytes come out the same from two runs that differ in the working
// directory, the output folder and the environment of the simulator.
TEST(LinkGuard, AFirmwareSeesTheSameAddressesInEveryRun) {
  TempDir one, two;
  const std::string project = rover_project(one_mcu(ADDRESS_PROBE), "", 0.05);
  // The probe computes for tens of milliseconds of host time between HAL calls in an optimised
  // build, and for seconds in a sanitizer build on a loaded host; the hang check (5 s of host time
  // by default) must not end the run for it, which is not what this test is about.
  const std::string options = "--quiet --hang-timeout 120";
  const SearRun a = run_sear(one, project, options);
  setenv("SEAR_TEST_PADDING", std::string(777, 'x').c_str(), 1);
  const SearRun b = run_sear(two, project, options);
  unsetenv("SEAR_TEST_PADDING");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const std::string line = a.file("rover.main.console.log");
  ASSERT_NE(line.find("stack 0x"), std::string::npos) << line;
  EXPECT_EQ(line, b.file("rover.main.console.log"));
}

// A pin toggled every microsecond writes ~20 bytes of waveform per microsecond of sim time; at a
// limit of 0.05 MiB the file stops at the limit with the note as its last line.
TEST(LinkGuard, EveryFileStopsAtItsLimitWithANote) {
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project(one_mcu(FLOOD_PIN_PROBE), "", 0.2), "--quiet --max-file-mb 0.05");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  const std::uint64_t limit = static_cast<std::uint64_t>(0.05 * 1024 * 1024);
  const std::string vcd = run.file("rover.main.pins.vcd");
  EXPECT_LE(vcd.size(), limit);
  EXPECT_GT(vcd.size(), limit - 200);  // filled to within one line and the note
  const auto lines = lines_of(vcd);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.back().rfind("$comment truncated:", 0), 0u) << lines.back();
  EXPECT_NE(run.err.find("rover.main.pins.vcd reached its limit of 52428 bytes"), std::string::npos) << run.err;
  // The summary is whole however the outputs were cut, and names the file.
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_EQ(summary["status"], "completed");
  ASSERT_EQ(summary["truncated_files"].size(), 1u);
  EXPECT_EQ(fs::path(summary["truncated_files"][0].get<std::string>()).filename(), "rover.main.pins.vcd");
}

// The firmware writes its own host log; the file-size limit on its process stops it there.
TEST(LinkGuard, TheFirmwaresOwnOutputStopsAtTheLimitToo) {
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project(one_mcu(FLOOD_PRINT_PROBE), "", 0.5), "--quiet --max-file-mb 0.05");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  const std::string log = run.file("rover.main.host.log");
  const std::size_t limit = static_cast<std::size_t>(0.05 * 1024 * 1024);
  const std::string note = lines_of(log).back();
  EXPECT_EQ(note.rfind("# truncated:", 0), 0u) << note;
  // The limit, then a line break ending the line cut short, then the note with its own.
  EXPECT_LE(log.size(), limit + 1 + note.size() + 1);
  EXPECT_GE(log.size(), limit);
  EXPECT_EQ(log.rfind("host line 0,", 0), 0u);  // unbuffered: from the first line on
}

// With hal_call_cycles="0" a toggling loop takes no simulated time: 2048 pin events at one
// instant fill the queue, which is a hang, not a reason to write gigabytes.
TEST(LinkGuard, ALoopThatTakesNoSimulatedTimeIsAHang) {
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project(one_mcu(FLOOD_FREE_PROBE, " hal_call_cycles=\"0\""), "", 1.0), "--quiet");
  EXPECT_EQ(run.exit_code, 3) << run.err;
  EXPECT_NE(run.err.find("hung: it wrote 2048 pin or port events without its clock moving"), std::string::npos) << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_EQ(summary["mcu_stops"][0]["kind"], "hung");
  EXPECT_DOUBLE_EQ(summary["mcu_stops"][0]["sim_time_s"].get<double>(), 0.0);
}

// With hal_call_cycles="1" at 16 MHz each call costs llround(62.5) = 63 ns, so a toggling loop
// fills the 2048-event queue eight times a quantum: each full queue is drained mid-call and the
// run goes on, every edge 63 ns after the one before (it was once taken for corruption).
TEST(LinkGuard, AQueueFilledMidQuantumIsDrainedAndEveryEdgeKept) {
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project(one_mcu(FLOOD_FREE_PROBE, " hal_call_cycles=\"1\""), "", 0.01), "--quiet");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  long long last = -1, edges = 0;
  bool spaced = true;
  for (const auto& line : lines_of(run.file("rover.main.pins.vcd"))) {
    if (line.empty() || line[0] != '#') continue;
    const long long t = std::stoll(line.substr(1));
    if (t == 0) continue;  // the initial values
    if (last > 0 && t - last != 63) spaced = false;
    last = t;
    ++edges;
  }
  EXPECT_TRUE(spaced);
  // From the first toggle, a few calls in, to the 10 ms end: 10 ms / 63 ns = 158 730 calls.
  EXPECT_GE(edges, 158720);
  EXPECT_LE(edges, 158731);
}

// Largest time_s of the `tx` lines of a UART log.
double last_tx_s(const std::string& log) {
  double last = 0;
  for (const auto& line : lines_of(log)) {
    std::istringstream in(line);
    double t = 0;
    std::string dir;
    if (line.empty() || line[0] == '#' || !(in >> t >> dir) || dir != "tx") continue;
    last = std::max(last, t);
  }
  return last;
}

// 82 bytes at 1200 baud leave one every 8.333 ms until ~0.68 s. A run of 0.3 s holds those that
// left by then, and none stamped later: 0.3 s / 8.333 ms = 36 bytes at most.
TEST(LinkGuard, NoByteIsStampedAfterTheRunsEnd) {
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project(one_mcu(LATE_WAIT_PROBE), "", 0.3), "--quiet");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  const std::string log = run.file("rover.main.uart0.log");
  EXPECT_LE(last_tx_s(log), 0.3);
  EXPECT_GT(last_tx_s(log), 0.3 - 10.0 / 1200);
  EXPECT_LE(run.file("rover.main.uart0.tx.bin").size(), 36u);
}

// It crashes 20 ms after its text was queued: the first 16 bytes had to leave (8.333 ms each)
// before the other 66 fit into the UART, so it crashed at 133.3 + 20 ms, and its log holds only
// the bytes that had left by then, although the run goes on (--keep-going) past the times the
// rest were due.
TEST(LinkGuard, NoByteIsStampedAfterTheMcuStopped) {
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project(one_mcu(LATE_CRASH_PROBE), "", 1.0), "--quiet --keep-going");
  EXPECT_EQ(run.exit_code, 3) << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  const double crashed_s = summary["mcu_stops"][0]["sim_time_s"].get<double>();
  EXPECT_NEAR(crashed_s, 16 * 10.0 / 1200 + 0.020, 1e-4);  // plus a few 3.125 us calls
  EXPECT_LE(last_tx_s(run.file("rover.main.uart0.log")), crashed_s);
  EXPECT_GT(last_tx_s(run.file("rover.main.uart0.log")), crashed_s - 10.0 / 1200);
  const auto console = lines_of(run.file("rover.main.console.log"));
  ASSERT_FALSE(console.empty());
  EXPECT_LE(std::stod(console.back()), crashed_s);
}

}  // namespace
}  // namespace sear::test
