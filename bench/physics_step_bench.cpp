// The cost of one physics step of the bundled default project (rover on heightmap among obstacles),
// with the real-time factor it implies: sim seconds per wall second for physics alone (wall clock,
// UseRealTime, as bench/run_rtf.sh measures whole runs), and the contact points per step; for the
// direct solver (the default) and the iterative one at several sweep counts. Then a pile of loose
// crates kept awake: where the direct solver's cost, the cube of a group's rows, overtakes.
#include <benchmark/benchmark.h>

#include <string>

#include "driving_project.hpp"
#include "runtime/simulation.hpp"

namespace {

// 0: the direct solver; n > 0: the iterative one with n sweeps.
void set_solver(sear::ProjectDesc& project, int sweeps) {
  project.world.solver = sweeps > 0 ? sear::WorldDesc::Solver::Iterative : sear::WorldDesc::Solver::Direct;
  if (sweeps > 0) project.world.solver_iterations = sweeps;
}

std::string solver_label(const sear::ProjectDesc& project) {
  return project.world.solver == sear::WorldDesc::Solver::Direct
             ? std::string("direct")
             : "iterative, " + std::to_string(project.world.solver_iterations) + " sweeps";
}

// The share of steps the direct solver took, and of those it gave up and the iterative one took.
void count_solvers(benchmark::State& state, const sear::Simulation& sim) {
  const auto& c = sim.physics().solver_counts();
  const double steps = static_cast<double>(c.direct + c.iterative);
  state.counters["direct"] = static_cast<double>(c.direct) / steps;
  state.counters["retaken"] = static_cast<double>(c.retaken) / steps;
}

sear::ProjectDesc default_project(int sweeps) {
  sear::ProjectDesc project = sear::bench::driving_default_project(0.8);
  set_solver(project, sweeps);
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
  count_solvers(state, *sim);
  // Contact points per step: the iterative solver's work grows with them times its sweeps, the
  // direct one's with the cube of the rows of each group of bodies that touch.
  state.counters["contacts"] = contacts / static_cast<double>(state.iterations());
  const double step_s = project.world.step_s;
  state.counters["sim_s_per_wall_s"] =
      benchmark::Counter(step_s * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel(solver_label(project));
}
BENCHMARK(BM_DefaultProjectStep)->Arg(0)->Arg(10)->Arg(20)->Arg(50)->Arg(200)->Unit(benchmark::kMicrosecond)->MinTime(2.0)->UseRealTime();

// A square pile of side x side x layers loose 0.3 m crates of 0.5 kg on flat ground, beside the
// parked rover, every crate kept awake (at rest a pile sleeps, and costs nothing): one group whose
// rows, three a contact point and four points a face that touches, the direct solver takes at once.
void BM_PileStep(benchmark::State& state) {
  sear::ProjectDesc project = sear::bench::driving_default_project(0.0);
  project.world.terrain = sear::TerrainDesc{};
  project.world.boxes.clear();
  project.world.trees.clear();
  project.world.walls.clear();
  project.world.meshes.clear();
  const int side = static_cast<int>(state.range(0)), layers = static_cast<int>(state.range(1));
  for (int i = 0; i < side * side * layers; ++i) {
    sear::BoxDesc crate;
    crate.name = "crate" + std::to_string(i);
    crate.size_m = {0.3, 0.3, 0.3};
    crate.mass_kg = 0.5;
    crate.xy_m = {-4.0 + 0.3 * (i % side), 4.0 + 0.3 * (i / side % side)};
    crate.on_ground = false;
    crate.z_m = 0.15 + 0.3 * (i / (side * side));
    project.world.boxes.push_back(crate);
  }
  set_solver(project, static_cast<int>(state.range(2)));
  sear::Simulation sim(project, 1);
  const dSpaceID space = sim.physics().dynamic_space();
  for (int g = 0; g < dSpaceGetNumGeoms(space); ++g)
    if (dBodyID body = dGeomGetBody(dSpaceGetGeom(space, g))) dBodySetAutoDisableFlag(body, 0);
  for (int i = 0; i < 200; ++i) sim.step();  // settled on each other
  double contacts = 0;
  for (auto _ : state) {
    sim.step();
    contacts += static_cast<double>(sim.physics().contact_count());
  }
  state.counters["contacts"] = contacts / static_cast<double>(state.iterations());
  count_solvers(state, sim);
  state.SetLabel(std::to_string(side * side * layers) + " crates, " + solver_label(project));
}
BENCHMARK(BM_PileStep)
    ->ArgsProduct({{2, 3}, {1, 2}, {0, 20}})
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(1.0)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
