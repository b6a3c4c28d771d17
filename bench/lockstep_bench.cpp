// The cost of lockstep itself: the default world stepped alone, and with one MCU whose firmware
// only calls delay_ms(1), so that each quantum is one hand-off to the firmware and back; and the
// cost of a HAL call that needs no hand-off, timed inside a firmware. Times and rates are wall
// clock (UseRealTime): the firmware runs in a process of its own, whose time this process's CPU
// clock does not see, and waiting for it is what a user waits for.
#include <benchmark/benchmark.h>

#include <regex>
#include <stdexcept>

#include "driving_project.hpp"
#include "runtime/lockstep.hpp"

namespace {

// The default world with its rover driving straight on a script, and `firmware` (if any) on one
// MCU wired to nothing.
sear::ProjectDesc bench_project(const char* firmware, double hal_call_cycles) {
  sear::ProjectDesc project = sear::bench::driving_default_project(0.6);
  if (firmware) {
    sear::McuDesc mcu;
    mcu.name = "bench";
    mcu.firmware_executable = firmware;
    mcu.hal_call_cycles = hal_call_cycles;
    project.robots.at(0).mcus.push_back(mcu);
  }
  return project;
}

struct ConsoleLine : sear::McuListener {
  std::string line, last;
  void on_events(std::size_t, const sear_event* events, std::size_t count) override {
    for (std::size_t i = 0; i < count; ++i) {
      const sear_event& e = events[i];
      if (e.kind != SEAR_EVENT_UART_TX) continue;
      if (e.value == '\n') last = line, line.clear();
      else line.push_back(static_cast<char>(e.value));
    }
  }
  void on_stop(std::size_t, std::int64_t) override {}
};

constexpr std::int64_t kRebuildNs = 20'000'000'000;  // keeps the rover inside the arena

void BM_StepWithoutFirmware(benchmark::State& state) {
  const auto project = bench_project(nullptr, 0);
  auto sim = std::make_unique<sear::Simulation>(project, 1);
  for (auto _ : state) {
    if (sim->time_ns() >= kRebuildNs) {
      state.PauseTiming();
      sim = std::make_unique<sear::Simulation>(project, 1);
      state.ResumeTiming();
    }
    sim->step();
  }
  state.counters["sim_s_per_wall_s"] = benchmark::Counter(1e-3 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_StepWithoutFirmware)->Unit(benchmark::kMicrosecond)->MinTime(2.0)->UseRealTime();

void BM_StepWithIdleFirmware(benchmark::State& state) {
  const auto project = bench_project(BENCH_IDLE_FIRMWARE, 50);
  ConsoleLine console;
  auto sim = std::make_unique<sear::Simulation>(project, 1);
  auto lockstep = std::make_unique<sear::Lockstep>(*sim, project, sear::LockstepOptions{"/tmp", sear::McuRunOptions{}, false}, console);
  for (auto _ : state) {
    if (sim->time_ns() >= kRebuildNs) {
      state.PauseTiming();
      lockstep.reset();
      sim = std::make_unique<sear::Simulation>(project, 1);
      lockstep = std::make_unique<sear::Lockstep>(*sim, project, sear::LockstepOptions{"/tmp", sear::McuRunOptions{}, false}, console);
      state.ResumeTiming();
    }
    if (!lockstep->step()) state.SkipWithError("the firmware stopped");
  }
  state.counters["sim_s_per_wall_s"] = benchmark::Counter(1e-3 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_StepWithIdleFirmware)->Unit(benchmark::kMicrosecond)->MinTime(2.0)->UseRealTime();

// One-shot: the firmware times 20 million digital_read() calls on the host's clock.
void BM_HalCallWithoutExchange(benchmark::State& state) {
  const auto project = bench_project(BENCH_HAL_CALL_FIRMWARE, 0);
  for (auto _ : state) {
    ConsoleLine console;
    sear::Simulation sim(project, 1);
    sear::LockstepOptions options;
    options.out_dir = "/tmp";
    options.mcu.hang_timeout_s = 60;
    sear::Lockstep lockstep(sim, project, options, console);
    while (console.last.empty() && sim.time_ns() < 1'000'000'000) lockstep.step();
    std::smatch m;
    if (!std::regex_search(console.last, m, std::regex("ns per HAL call ([0-9.]+)"))) {
      state.SkipWithError("no timing from the firmware");
      break;
    }
    state.counters["ns_per_hal_call"] = std::stod(m[1]);
  }
}
BENCHMARK(BM_HalCallWithoutExchange)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
