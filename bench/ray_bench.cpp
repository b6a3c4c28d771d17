// The cost of the bump lever's rays in the default world: ten parallel 2 cm rays under the
// rover's nose, asked one sensor at a time (one pass over the world's geoms per ray) and as one
// RangeSensorSet (one pass per lever); in the default world, and with eight rovers in it, where
// every pass also walks every other robot's parts.
#include <benchmark/benchmark.h>

#include <cmath>

#include "driving_project.hpp"
#include "runtime/simulation.hpp"
#include "sensors/range_sensor.hpp"

namespace {

// The default project's lever: <bump pos="0.14 0 -0.01" width="0.18" reach="0.02"/>, laid out as
// the MCU bridge lays it (rays at most 2 cm apart across the width).
std::vector<sear::RangeBeam> lever_beams() {
  const double width = 0.18;
  const int n = static_cast<int>(std::ceil(width / 0.02)) + 1;
  std::vector<sear::RangeBeam> beams;
  for (int i = 0; i < n; ++i) {
    sear::RangeBeam beam;
    beam.position_m = {0.14, width * (static_cast<double>(i) / (n - 1) - 0.5), -0.01};
    beam.max_range_m = 0.02;
    beams.push_back(beam);
  }
  return beams;
}

sear::ProjectDesc project_with(int robots) {
  sear::ProjectDesc project = sear::bench::driving_default_project(0.6);
  const sear::RobotDesc rover = project.robots.at(0);
  const double poses[][3] = {{0, -6, 90}, {-6, 0, 180}, {6, 6, -90}, {-7, -7, 45}, {7, -9, 135}, {-8, 7, -45}, {9, 1, 200}};
  for (int i = 1; i < robots; ++i) {
    sear::RobotDesc r = rover;
    r.name = "rover" + std::to_string(i + 1);
    r.start_xy_m = {poses[i - 1][0], poses[i - 1][1]};
    r.start_yaw_rad = poses[i - 1][2] * sear::kDegToRad;
    project.robots.push_back(r);
  }
  return project;
}

void BM_LeverRayByRay(benchmark::State& state) {
  const sear::ProjectDesc project = project_with(static_cast<int>(state.range(0)));
  sear::Simulation sim(project, 1);
  for (int i = 0; i < 300; ++i) sim.step();
  std::vector<sear::RangeSensor> rays;
  for (const auto& beam : lever_beams()) rays.emplace_back(beam);
  const auto& rover = sim.robot(0);
  bool closed = false;
  for (auto _ : state) {
    closed = false;
    for (const auto& ray : rays) closed = closed || ray.measure(sim.physics(), rover.chassis_body(), rover.entity()).hit;
    benchmark::DoNotOptimize(closed);
  }
  state.SetLabel(closed ? "pressed" : "free");
}
BENCHMARK(BM_LeverRayByRay)->Arg(1)->Arg(8)->Unit(benchmark::kNanosecond);

void BM_LeverSet(benchmark::State& state) {
  const sear::ProjectDesc project = project_with(static_cast<int>(state.range(0)));
  sear::Simulation sim(project, 1);
  for (int i = 0; i < 300; ++i) sim.step();
  const sear::RangeSensorSet lever(lever_beams());
  const auto& rover = sim.robot(0);
  bool closed = false;
  for (auto _ : state) {
    closed = lever.any_hit(sim.physics(), rover.chassis_body(), rover.entity());
    benchmark::DoNotOptimize(closed);
  }
  state.SetLabel(closed ? "pressed" : "free");
}
BENCHMARK(BM_LeverSet)->Arg(1)->Arg(8)->Unit(benchmark::kNanosecond);

}  // namespace

BENCHMARK_MAIN();
