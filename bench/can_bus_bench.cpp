// The simulated CAN bus's cost: run_until on an idle bus (the issue asks well under 1 us per
// quantum), and a fully loaded 1 Mbit/s bus (frames back to back from three senders, decided in
// 1 ms quanta), reported as bus seconds decided per wall-clock second (the real-time factor).
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "runtime/can_bus.hpp"

namespace {

void BM_IdleBusQuantum(benchmark::State& state) {
  sear::CanBus bus(1'000'000);
  for (int i = 0; i < 4; ++i) bus.set_listening(bus.add_node("n"), true);
  std::vector<sear::CanTransfer> done;
  std::int64_t t = 0;
  for (auto _ : state) {
    t += 1'000'000;
    bus.run_until(t, done);
    benchmark::DoNotOptimize(done.data());
  }
}
BENCHMARK(BM_IdleBusQuantum);

void BM_LoadedBus1Mbit(benchmark::State& state) {
  std::mt19937 rng(1);
  std::vector<sear::CanFrame> frames(4096);
  for (auto& f : frames) {
    f.extended = (rng() & 3) == 0;
    f.id = static_cast<std::uint32_t>(rng()) & (f.extended ? 0x1FFFFFFFu : 0x7FFu);
    f.dlc = static_cast<std::uint8_t>(rng() % 9);
    for (int b = 0; b < f.dlc; ++b) f.data[static_cast<std::size_t>(b)] = static_cast<std::uint8_t>(rng());
  }
  constexpr std::int64_t kQuantumNs = 1'000'000;
  constexpr int kQuanta = 1000;  // one second of bus time per iteration
  std::size_t decided = 0;
  for (auto _ : state) {
    sear::CanBus bus(1'000'000);
    std::size_t nodes[3];
    for (auto& n : nodes) {
      n = bus.add_node("mcu");
      bus.set_listening(n, true);
    }
    std::vector<sear::CanTransfer> done;
    std::size_t next = 0;
    for (int q = 0; q < kQuanta; ++q) {
      const std::int64_t t0 = q * kQuantumNs;
      // Each sender keeps a few frames queued, as firmware filling its three TX buffers does.
      for (std::size_t n : nodes)
        while (bus.pending(n) < 3) bus.request(n, t0, frames[next++ % frames.size()], 0);
      done.clear();
      bus.run_until(t0 + kQuantumNs, done);
      decided += done.size();
    }
    benchmark::DoNotOptimize(decided);
  }
  state.counters["frames_per_bus_s"] =
      benchmark::Counter(static_cast<double>(decided) / static_cast<double>(state.iterations()));
  state.counters["realtime_factor"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_LoadedBus1Mbit)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
