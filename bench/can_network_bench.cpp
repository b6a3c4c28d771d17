// The CAN network's cost per quantum, on the simulator's side of lockstep: a bus nobody uses
// (the target: under 1 us a quantum), and a bus the host bridge keeps fully loaded at
// 1 Mbit/s, which must be decided far faster than real time. The host's end is a stand-in that
// offers frames as fast as the bus can take them; the SocketCAN socket's own cost is the kernel's
// (one non-blocking recvmmsg per quantum) and is checked for correctness in the vcan tests.
#include <benchmark/benchmark.h>

#include "driving_project.hpp"
#include "runtime/can_network.hpp"
#include "runtime/simulation.hpp"

namespace {

struct FloodingHost : sear::HostCanEnd {
  std::size_t per_read = 0;  // frames offered at each look, 0: none
  std::uint64_t written = 0;
  std::uint32_t next_id = 0;
  std::size_t read_available(std::vector<sear::CanFrame>& out) override {
    for (std::size_t i = 0; i < per_read; ++i) {
      sear::CanFrame f;
      f.id = next_id++ & 0x7FF;
      f.dlc = 8;
      f.data = {1, 2, 3, 4, 5, 6, 7, 8};
      out.push_back(f);
    }
    return per_read;
  }
  void write(const sear::CanFrame&) override { ++written; }
};

struct FrameCount : sear::RunTap {
  std::uint64_t frames = 0;
  void on_can_frame(std::size_t, const sear::CanTransfer& t) override { frames += t.acked; }
};

sear::ProjectDesc can_project(std::uint32_t bitrate, double broadcast_hz) {
  sear::ProjectDesc project = sear::bench::driving_default_project(0.6);
  sear::CanBusDesc bus;
  bus.name = "body";
  bus.bitrate = bitrate;
  bus.broadcast_hz = broadcast_hz;
  project.can_buses.push_back(bus);
  return project;
}

constexpr std::int64_t kQuantumNs = 1'000'000;

void BM_IdleBusPerQuantum(benchmark::State& state) {
  const auto project = can_project(500000, 0);
  const sear::Simulation sim(project, 1);
  const std::vector<std::unique_ptr<sear::McuBridge>> no_mcus;
  sear::CanNetwork network(project, no_mcus, nullptr);
  std::int64_t t = 0;
  for (auto _ : state) {
    network.begin_quantum(sim, t, t + kQuantumNs);
    network.finish_quantum(t, t + kQuantumNs);
    t += kQuantumNs;
  }
}
BENCHMARK(BM_IdleBusPerQuantum)->Unit(benchmark::kNanosecond);

// The host offers 10 frames each quantum, more than the ~8 a 1 Mbit/s bus carries in 1 ms, so the
// bus runs back to back. SEAR's broadcast node (once a second) is the controller that acks them.
void BM_FullBusFromTheHost(benchmark::State& state) {
  const auto project = can_project(1000000, 1);
  const sear::Simulation sim(project, 1);
  const std::vector<std::unique_ptr<sear::McuBridge>> no_mcus;
  std::int64_t t = 0;
  std::uint64_t frames = 0;
  std::int64_t sim_ns = 0;
  for (auto _ : state) {
    state.PauseTiming();
    FrameCount count;
    sear::CanNetwork network(project, no_mcus, &count);
    FloodingHost host;
    host.per_read = 10;
    network.attach_host("body", &host);
    t = 0;
    state.ResumeTiming();
    for (int q = 0; q < 1000; ++q) {  // one simulated second
      network.begin_quantum(sim, t, t + kQuantumNs);
      network.finish_quantum(t, t + kQuantumNs);
      t += kQuantumNs;
    }
    frames += count.frames;
    sim_ns += t;
  }
  state.counters["frames_per_sim_s"] = static_cast<double>(frames) / (static_cast<double>(sim_ns) * 1e-9);
  state.counters["sim_s_per_wall_s"] = benchmark::Counter(static_cast<double>(sim_ns) * 1e-9, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_FullBusFromTheHost)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
