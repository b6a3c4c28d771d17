// The cost of one physics step of the bundled default project (rover on heightmap among obstacles),
// with the real-time factor it implies: sim seconds per wall second for physics alone (wall clock,
// UseRealTime, as bench/run_rtf.sh measures whole runs), and the contact points per step.
#include <benchmark/benchmark.h>


#include "driving_project.hpp"
#include "runtime/simulation.hpp"

namespace {

sear::ProjectDesc default_project(int solver_iterations) {
  sear::ProjectDesc project = sear::bench::driving_default_project(0.8);
  if (solver_iterations > 0) project.world.solver_iterations = solver_iterations;
  return project;
}

// Steps the default project from its start, with the rover driving straight on; the
// world is rebuilt (untimed) every 30 simulated seconds so each step stays representative.
void BM_DefaultProjectStep(benchmark::State& state) {
  const sear::ProjectDesc project = default_project(static_cast<int>(state.range(0)));
  auto sim = std::make_unique<sear::Simulation>(project, project.run.seed);
  const std::int64_t end_ns = static_cast<std::int64_t>(project.run.duration_s * 1e9);
  double contacts = 0;
  for (auto _ : state) {
    if (sim->time_ns() >= end_ns) {
      state.PauseTiming();
      sim = std::make_unique<sear::Simulation>(project, project.run.seed);
      state.ResumeTiming();
    }
    sim->step();
    contacts += static_cast<double>(sim->physics().contact_count());
  }
  // Contact points per step: QuickStep's work grows with them times its iterations.
  state.counters["contacts"] = contacts / static_cast<double>(state.iterations());
  const double step_s = project.world.step_s;
  state.counters["sim_s_per_wall_s"] =
      benchmark::Counter(step_s * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel("solver_iterations=" + std::to_string(project.world.solver_iterations));
}
BENCHMARK(BM_DefaultProjectStep)->Arg(0)->Arg(10)->Arg(50)->Arg(200)->Unit(benchmark::kMicrosecond)->MinTime(2.0)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
