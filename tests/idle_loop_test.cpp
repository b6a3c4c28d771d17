// The idle-loop check (hal/runtime/idle.c) moves a firmware that waits for an interrupt without
// HAL calls on to its next interrupt, and must never take computing for such a wait: a firmware
// that computes for tens of milliseconds of host time between HAL calls (in floating-point
// registers, in memory, or in general registers only), with a timer handler
// attached, prints exactly the times the HAL's cost model gives, byte for byte on a quiet and on a
// fully loaded host; and a thousand `while (!flag) {}` waits on a 1 kHz timer each end at their tick.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <regex>
#include <vector>

#include "firmware_run.hpp"

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

TEST(IdleLoop, AThousandWaitsOnA1kHzTimerEachEndAtTheirTick) {
  TempDir dir;
  const auto run = run_sear(dir, probe_project(TICK_WAIT_PROBE, 1.1));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string console = run.file("rover.main.console.log");
  // Tick k falls due at 1006.25 us + k ms (the timer started at 6.25 us), so the last of 1000 at
  // 1000006.25 us; micros() acts right there.
  EXPECT_NE(console.find("1000 of 1000 waits ended at their tick, the last at 1000006 us"), std::string::npos)
      << console;
}

}  // namespace
}  // namespace sear::test
