// The idle-loop check (hal/runtime/idle.c) moves a firmware that waits for an interrupt without
// HAL calls on to its next interrupt, and must never take computing for such a wait: a firmware
// that computes for tens of milliseconds of host time between HAL calls (in floating-point
// registers, in memory, or in general registers only), with a timer handler
// attached, prints exactly the times the HAL's cost model gives, byte for byte on a quiet and on a
// fully loaded host; and a thousand `while (!flag) {}` waits on a 1 kHz timer each end at their tick.
// `for (;;);` is no wait but the idiom for "stop here": the MCU halts at the moment it entered the
// loop, its timer still firing and its queued bytes still leaving, and the run goes on to its end.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <regex>
#include <vector>

#include "firmware_run.hpp"
#include "model_run.hpp"

namespace sear::test {
namespace {

constexpr std::int64_t kCallNs = 3125;  // hal_call_cycles 50 at clock_hz 16 MHz, the defaults

std::string probe_project(const char* firmware, double duration_s) {
  return rover_project(std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + firmware +
                           "\"/>\n    </mcu>\n",
                       "", duration_s);
}

// What tests/firmware/compute_probe.c prints per round, from the cost model alone: hal_init,
// uart_begin and irq_timer_start act at 0, c and 2c, the timer's first tick falls due 1 ms after
// the third; each round is four micros() calls 1c apart (the computing between them takes no
// simulated time) and a delay_ms(2) that lasts 2 ms from its own call; the tick count is read just
// after the fourth micros(), whose call delivers every tick due by the moment it acts.
std::vector<std::string> expected_rounds() {
  std::vector<std::string> lines;
  const std::int64_t first_tick = 2 * kCallNs + 1'000'000;
  std::int64_t t = 3 * kCallNs;
  const unsigned long counts[] = {40000000, 40001000, 40002000};
  for (int r = 0; r < 3; ++r) {
    const std::int64_t last_call = t + 3 * kCallNs;
    const long ticks = last_call >= first_tick ? (last_call - first_tick) / 1'000'000 + 1 : 0;
    char line[200];
    std::snprintf(line, sizeof line, "round %d: %lld %lld %lld %lld us, grown [0-9.]+, counted %lu, mixed [0-9]+, ticks %ld",
                  r, static_cast<long long>(t / 1000), static_cast<long long>((t + kCallNs) / 1000),
                  static_cast<long long>((t + 2 * kCallNs) / 1000), static_cast<long long>(last_call / 1000),
                  counts[r], ticks);
    lines.push_back(line);
    t = last_call + kCallNs + 2'000'000;
  }
  return lines;
}

// Busy-spinning processes, one per core of these 2-core machines, for as long as this lives;
// they die with the test even if it crashes.
class HostLoad {
 public:
  explicit HostLoad(int processes) {
    const pid_t parent = getpid();
    for (int i = 0; i < processes; ++i) {
      const pid_t pid = fork();
      if (pid == 0) {
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (getppid() != parent) _exit(0);
        for (volatile unsigned long spin = 0;; spin = spin + 1) {
        }
      }
      if (pid > 0) pids_.push_back(pid);
    }
  }
  ~HostLoad() {
    for (const pid_t pid : pids_) kill(pid, SIGKILL);
    for (const pid_t pid : pids_) waitpid(pid, nullptr, 0);
  }
  HostLoad(const HostLoad&) = delete;
  HostLoad& operator=(const HostLoad&) = delete;

 private:
  std::vector<pid_t> pids_;
};

TEST(IdleLoop, ComputingBetweenHalCallsIsNeverTakenForWaitingQuietOrLoaded) {
  // 3 rounds of 2 ms and the printing of 3 lines of ~110 bytes at 115200 baud (87 us a byte, 29 ms) fit.
  const std::string project = probe_project(COMPUTE_PROBE, 0.05);
  // Each computation lasts tens of milliseconds of host time in an optimised build and seconds in
  // a sanitizer build beside two busy processes; the hang check (5 s of host time by default)
  // must not end the run for it, which is not what this test is about.
  const std::string generous = "--hang-timeout 120";
  TempDir quiet_dir;
  const auto quiet = run_sear(quiet_dir, project, generous);
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  const std::string console = quiet.file("rover.main.console.log");
  for (const auto& line : expected_rounds())
    EXPECT_TRUE(std::regex_search(console, std::regex(line))) << "no '" << line << "' in\n" << console;

  TempDir loaded_dir;
  SearRun loaded;
  {
    const HostLoad load(2);
    loaded = run_sear(loaded_dir, project, generous);
  }
  ASSERT_EQ(loaded.exit_code, 0) << loaded.err;
  // Every byte, the values computed and the times the console stamps included.
  EXPECT_EQ(loaded.file("rover.main.console.log"), console);
}

// tests/firmware/tick_wait_probe.c as this tree builds it, and unoptimised (-O0, as a Debug build
// compiles it: the flag is loaded and tested on every pass, and the loop is no empty one).
class Waits : public ::testing::TestWithParam<const char*> {};

TEST_P(Waits, AThousandWaitsOnA1kHzTimerEachEndAtTheirTick) {
  TempDir dir;
  const auto run = run_sear(dir, probe_project(GetParam(), 1.1));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string console = run.file("rover.main.console.log");
  // Tick k falls due at 1006.25 us + k ms (the timer started at 6.25 us), so the last of 1000 at
  // 1000006.25 us; micros() acts right there.
  EXPECT_NE(console.find("1000 of 1000 waits ended at their tick, the last at 1000006 us"), std::string::npos)
      << console;
  // Each of those loops was a wait, never a halt.
  EXPECT_EQ(run.err.find("halted"), std::string::npos) << run.err;
  EXPECT_TRUE(nlohmann::json::parse(run.file("summary.json"))["mcu_halts"].empty());
}

INSTANTIATE_TEST_SUITE_P(IdleLoop, Waits, ::testing::Values(TICK_WAIT_PROBE, TICK_WAIT_O0_PROBE),
                         [](const auto& param) { return param.index == 0 ? "AsBuilt" : "Unoptimised"; });

// tests/firmware/halt_probe.c: hal_init, uart_begin, pin_mode, irq_timer_start and uart_print act
// at 0, c, 2c, 3c and 4c; the loop begins when the last call's cost is charged, at 5c (6c after
// irq_disable() in the interrupts-off build). The timer's tick k falls due at 3c + k ms.
constexpr std::int64_t kHaltNs = 5 * kCallNs;
constexpr std::int64_t kFirstTickNs = 3 * kCallNs + 1'000'000;
const std::string kHaltLine = "halting: every byte of this line leaves after the loop began.\n";

// The run's summary holds exactly one halt, of rover.main at halt_ns, with its interrupts
// "on" or "off".
void expect_one_halt(const nlohmann::json& summary, std::int64_t halt_ns, const char* interrupts) {
  ASSERT_EQ(summary["mcu_halts"].size(), 1u) << summary.dump();
  EXPECT_EQ(summary["mcu_halts"][0]["mcu"], "rover.main");
  EXPECT_DOUBLE_EQ(summary["mcu_halts"][0]["sim_time_s"].get<double>(), static_cast<double>(halt_ns) * 1e-9);
  EXPECT_EQ(summary["mcu_halts"][0]["interrupts"], interrupts);
}

// (time in ns, byte) of each "tx" line of a UART log ("S.NNNNNNNNN tx 4c").
std::vector<std::pair<std::int64_t, int>> sent_bytes(const std::string& log) {
  std::vector<std::pair<std::int64_t, int>> bytes;
  const std::regex line("^(\\d+)\\.(\\d{9}) tx ([0-9a-f]{2})$");
  std::smatch m;
  for (const auto& l : lines_of(log))
    if (std::regex_match(l, m, line))
      bytes.emplace_back(std::stoll(m[1]) * 1000000000 + std::stoll(m[2]), std::stoi(m[3], nullptr, 16));
  return bytes;
}

TEST(Halt, AnEndlessEmptyLoopHaltsTheMcuWhileItsTimerAndItsUartGoOnToTheRunsEnd) {
  TempDir dir;
  const double duration_s = 0.45;
  const auto run = run_sear(dir, probe_project(HALT_PROBE, duration_s));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("mcu rover.main halted at sim time 0.000016 s (an endless empty loop; its interrupts still "
                         "run); the run goes on"),
            std::string::npos)
      << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_EQ(summary["status"], "completed");
  EXPECT_TRUE(summary["mcu_stops"].empty());
  expect_one_halt(summary, kHaltNs, "on");
  EXPECT_NE(run.file("summary.txt").find("  mcu rover.main halted at sim time 0.000016 s"), std::string::npos);

  // Every byte of the line queued before the loop left, back to back at 9600 baud from the end of
  // the uart_print() call, 5c, the moment the loop began: byte n's stop bit ends n * 10 bit times
  // after (uart.c's rounding to the nanosecond).
  const auto sent = sent_bytes(run.file("rover.main.uart0.log"));
  ASSERT_GE(sent.size(), kHaltLine.size());
  for (std::size_t n = 1; n <= kHaltLine.size(); ++n) {
    EXPECT_EQ(sent[n - 1].first, kHaltNs + static_cast<std::int64_t>((n * 10'000'000'000ull + 4800) / 9600)) << n;
    EXPECT_EQ(sent[n - 1].second, static_cast<unsigned char>(kHaltLine[n - 1])) << n;
  }
  // The handler ran at every tick to the run's end: pin 13 went out LOW at 2c, then toggled at
  // each tick, 449 of them by 0.45 s (the 450th falls due 9.375 us after the end), at the tick's
  // own nanosecond; every 100th printed its count.
  const auto changes = vcd_changes(run.file("rover.main.pins.vcd"), vcd_id_of_pin(13));
  ASSERT_EQ(changes.size(), 2u + 449u);
  EXPECT_EQ(changes[1].time, 2 * kCallNs);
  for (std::size_t k = 1; k <= 449; ++k) {
    EXPECT_EQ(changes[k + 1].time, kFirstTickNs + static_cast<std::int64_t>(k - 1) * 1'000'000) << "tick " << k;
    EXPECT_EQ(changes[k + 1].value, k % 2 == 1 ? '1' : '0') << "tick " << k;
  }
  const std::string console = run.file("rover.main.console.log");
  for (const char* line : {"tick 100\n", "tick 200\n", "tick 300\n", "tick 400\n"})
    EXPECT_NE(console.find(line), std::string::npos) << console;

  // The same bytes in a second run.
  TempDir again_dir;
  const auto again = run_sear(again_dir, probe_project(HALT_PROBE, duration_s));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  for (const char* file : {"rover.main.console.log", "rover.main.uart0.log", "rover.main.pins.vcd"})
    EXPECT_EQ(again.file(file), run.file(file)) << file;
  EXPECT_EQ(nlohmann::json::parse(again.file("summary.json"))["mcu_halts"], summary["mcu_halts"]);
}

TEST(Halt, WithInterruptsOffTheMcuHaltsAndItsTimerNeverRuns) {
  TempDir dir;
  const auto run = run_sear(dir, probe_project(HALT_IRQ_OFF_PROBE, 0.05));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("mcu rover.main halted at sim time 0.000019 s (an endless empty loop with interrupts off; "
                         "nothing more runs on it)"),
            std::string::npos)
      << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  expect_one_halt(summary, kHaltNs + kCallNs, "off");
  // Pin 13 went out LOW and no tick ever toggled it.
  EXPECT_EQ(vcd_changes(run.file("rover.main.pins.vcd"), vcd_id_of_pin(13)).size(), 2u);
}

// GCC without optimisation (a Debug build, the sanitizers' build of these tests) compiles
// `for (;;) {}` to `nop; jmp .-1`, not `jmp .`: the MCU halts there all the same, at the same
// moment, and with interrupts off the run is not taken for hung.
TEST(Halt, UnoptimisedTheEndlessEmptyLoopHaltsAtTheSameMoment) {
  TempDir dir;
  const auto run = run_sear(dir, probe_project(HALT_O0_PROBE, 0.05));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("mcu rover.main halted at sim time 0.000016 s (an endless empty loop; its interrupts still "
                         "run); the run goes on"),
            std::string::npos)
      << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  expect_one_halt(summary, kHaltNs, "on");
  // Its timer still ran: 49 ticks by 0.05 s (the 50th falls due 9.375 us after the end).
  EXPECT_EQ(vcd_changes(run.file("rover.main.pins.vcd"), vcd_id_of_pin(13)).size(), 2u + 49u);

  TempDir off_dir;
  const auto off = run_sear(off_dir, probe_project(HALT_IRQ_OFF_O0_PROBE, 0.05));
  ASSERT_EQ(off.exit_code, 0) << off.err;
  expect_one_halt(nlohmann::json::parse(off.file("summary.json")), kHaltNs + kCallNs, "off");
}

}  // namespace
}  // namespace sear::test
