// Ray casting in the default world. A LIDAR's 361-ray scan (half a degree apart over 180 degrees,
// level, 0.3 m above the rover's centre) out to 8 m and to 1.5 m, through the static world's
// Embree BVH (static only, and with the moving bodies through ODE) beside the same rays through
// ODE alone; reports rays/s. Then the default rover's GP2D12 cone (2 degrees, 1 degree apart, 20
// rays to 1.5 m) and its bump lever: ten parallel 2 cm rays under its nose, asked one sensor at a
// time and as one RangeSensorSet, in the default world and with eight rovers in it.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <vector>

#include "driving_project.hpp"
#include "runtime/simulation.hpp"
#include "sensors/range_sensor.hpp"
#include "sensors/ray_scene.hpp"

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

// The rover of the default world, settled, and its pose.
struct Rover {
  Rover() : project(project_with(1)), sim(project, 1) {
    for (int i = 0; i < 300; ++i) sim.step();
    const dBodyID body = sim.robot(0).chassis_body();
    const dReal* p = dBodyGetPosition(body);
    const dReal* r = dBodyGetRotation(body);
    position << p[0], p[1], p[2];
    rotation << r[0], r[1], r[2], r[4], r[5], r[6], r[8], r[9], r[10];
  }
  sear::ProjectDesc project;
  sear::Simulation sim;
  Eigen::Vector3d position;
  Eigen::Matrix3d rotation;
};

sear::ScanFan lidar(double range_m) {
  sear::ScanFan fan;
  fan.position_m = {0.05, 0, 0.3};
  fan.first_angle_rad = 0;
  fan.step_rad = 0.5 * sear::kDegToRad;
  fan.count = 361;
  fan.max_range_m = range_m;
  return fan;
}

// The scan turned about the rover (each iteration looks another way, over other terrain) and
// pitched down by `pitch` (level rays over the flat start disc rarely meet the ground; a LIDAR
// tilted 3 degrees down meets it about 6.7 m out, on the hills; 15 degrees down, about 1.3 m).
Eigen::Matrix3d turned(const Eigen::Matrix3d& rotation, int iteration, double pitch_rad = 0) {
  return rotation * Eigen::AngleAxisd(0.7 * iteration, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
         Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
}

double range_of(const benchmark::State& state) { return static_cast<double>(state.range(0)) / 100; }
double pitch_of(const benchmark::State& state) { return static_cast<double>(state.range(1)) / 10 * sear::kDegToRad; }

void report(benchmark::State& state, std::size_t rays_per_iteration, int hits) {
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(rays_per_iteration) *
                                                    static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
  state.counters["hit%"] = 100.0 * hits / static_cast<double>(rays_per_iteration);
}

// Arguments: range in cm, downward pitch in tenths of a degree.
void BM_ScanBvhStaticOnly(benchmark::State& state) {
  const Rover rover;
  const sear::RayScene& scene = sear::RayScene::of(rover.sim.physics());
  const sear::RangeScan scan(lidar(range_of(state)));
  std::vector<float> cos_table(361), sin_table(361), d(361);
  for (int i = 0; i < 361; ++i) {
    cos_table[static_cast<std::size_t>(i)] = static_cast<float>(std::cos(0.5 * sear::kDegToRad * i));
    sin_table[static_cast<std::size_t>(i)] = static_cast<float>(std::sin(0.5 * sear::kDegToRad * i));
  }
  int k = 0;
  for (auto _ : state) {
    const Eigen::Matrix3d r = turned(rover.rotation, k++ % 9, pitch_of(state));
    scene.cast_fan(rover.position + r * scan.fan().position_m, -r.col(1), r.col(0), cos_table.data(),
                   sin_table.data(), 361, scan.fan().max_range_m, rover.sim.robot(0).entity(), d.data());
    benchmark::DoNotOptimize(d.data());
  }
  int hits = 0;
  for (float v : d) hits += std::isfinite(v);
  report(state, 361, hits);
}
BENCHMARK(BM_ScanBvhStaticOnly)->Args({800, 0})->Args({150, 0})->Args({800, 30})->Args({150, 150})->Unit(benchmark::kMicrosecond);

void BM_ScanBvh(benchmark::State& state) {
  const Rover rover;
  const sear::RangeScan scan(lidar(range_of(state)));
  std::vector<float> d(361);
  int k = 0;
  for (auto _ : state) {
    scan.scan(rover.sim.physics(), rover.position, turned(rover.rotation, k++ % 9, pitch_of(state)),
              rover.sim.robot(0).entity(), d.data());
    benchmark::DoNotOptimize(d.data());
  }
  int hits = 0;
  for (float v : d) hits += std::isfinite(v);
  report(state, 361, hits);
}
BENCHMARK(BM_ScanBvh)->Args({800, 0})->Args({150, 0})->Args({800, 30})->Args({150, 150})->Unit(benchmark::kMicrosecond);

// The same rays through ODE alone; beside each scan the BVH path casts them too (untimed by the
// framework, clocked here), so that the ratio of the two comes from one run on the same rays.
void BM_ScanOdeOnly(benchmark::State& state) {
  const Rover rover;
  const sear::RangeScan scan(lidar(range_of(state)));
  std::vector<float> d(361), bvh(361);
  int k = 0, disagree = 0;
  double ode_s = 0, bvh_s = 0;
  using Clock = std::chrono::steady_clock;
  for (auto _ : state) {
    const Eigen::Matrix3d r = turned(rover.rotation, k++ % 9, pitch_of(state));
    const auto t0 = Clock::now();
    scan.scan_ode_only(rover.sim.physics(), rover.position, r, rover.sim.robot(0).entity(), d.data());
    const auto t1 = Clock::now();
    benchmark::DoNotOptimize(d.data());
    state.PauseTiming();
    const auto t2 = Clock::now();
    scan.scan(rover.sim.physics(), rover.position, r, rover.sim.robot(0).entity(), bvh.data());
    const auto t3 = Clock::now();
    ode_s += std::chrono::duration<double>(t1 - t0).count();
    bvh_s += std::chrono::duration<double>(t3 - t2).count();
    // How many rays differ by more than a millimetre.
    for (std::size_t i = 0; i < d.size(); ++i)
      disagree += !((std::isinf(d[i]) && std::isinf(bvh[i])) || std::abs(d[i] - bvh[i]) < 1e-3f);
    state.ResumeTiming();
  }
  int hits = 0;
  for (float v : d) hits += std::isfinite(v);
  report(state, 361, hits);
  state.counters["disagree"] = disagree;
  state.counters["bvh_speedup"] = bvh_s > 0 ? ode_s / bvh_s : 0;
}
BENCHMARK(BM_ScanOdeOnly)->Args({800, 0})->Args({150, 0})->Args({800, 30})->Args({150, 150})->Unit(benchmark::kMicrosecond);

// The default project's GP2D12 (sim/devices/sharp_ranger.cpp: half-angle 2 degrees, 1 degree
// apart, 1.5 m) on its left mount; argument 0: through the BVH, 1: through ODE alone.
void BM_IrCone(benchmark::State& state) {
  const Rover rover;
  sear::RangeBeam beam;
  beam.position_m = {0.15, 0.06, 0.02};
  beam.yaw_rad = 30 * sear::kDegToRad;
  beam.half_angle_rad = 2 * sear::kDegToRad;
  beam.resolution_rad = 1 * sear::kDegToRad;
  beam.max_range_m = 1.5;
  const sear::RangeSensor ir(beam);
  const bool ode_only = state.range(0) != 0;
  int k = 0, hits = 0;
  for (auto _ : state) {
    // Turned and pitched down 10 degrees so that about half the cones meet the ground.
    const int i = k++;
    const Eigen::Matrix3d r = turned(rover.rotation, i % 9, (i % 2 ? 10 : 0) * sear::kDegToRad);
    const int self = rover.sim.robot(0).entity();
    const sear::RangeReading reading = ode_only ? ir.measure_ode_only(rover.sim.physics(), rover.position, r, self)
                                                : ir.measure(rover.sim.physics(), rover.position, r, self);
    hits += reading.hit;
    benchmark::DoNotOptimize(reading);
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(ir.directions().size()) *
                                                    static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
  state.counters["hit%"] = 100.0 * hits / static_cast<double>(state.iterations());
}
BENCHMARK(BM_IrCone)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// The lever's rays one at a time through ODE alone (the path before the BVH), beside
// BM_LeverRayByRay and BM_LeverSet above.
void BM_LeverOdeOnly(benchmark::State& state) {
  const Rover rover;
  std::vector<sear::RangeSensor> rays;
  for (const auto& beam : lever_beams()) rays.emplace_back(beam);
  bool closed = false;
  for (auto _ : state) {
    closed = false;
    for (const auto& ray : rays)
      closed = closed || ray.measure_ode_only(rover.sim.physics(), rover.position, rover.rotation,
                                              rover.sim.robot(0).entity()).hit;
    benchmark::DoNotOptimize(closed);
  }
  state.SetLabel(closed ? "pressed" : "free");
}
BENCHMARK(BM_LeverOdeOnly)->Unit(benchmark::kNanosecond);

// Building the default world's BVH from its static space (done once per world).
void BM_BuildScene(benchmark::State& state) {
  const Rover rover;
  for (auto _ : state) {
    const sear::RayScene scene(rover.sim.physics());
    benchmark::DoNotOptimize(scene.triangle_count());
  }
}
BENCHMARK(BM_BuildScene)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
