// An unpowered rover on flat ground stays where it settled: docs/project.md, `motor`: gear_friction is the
// gearbox's Coulomb friction, "which holds the wheels when unpowered". On flat ground nothing
// pushes the rover at all, so any drift is the solver's, not the model's. The direct solver (the
// default) solves the rows exactly, and what is left is the model's own slip, bounded below; the
// iterative one at its default 20 sweeps lets a resting rover creep about 0.6 mm/s (docs/models.md).
#include <gtest/gtest.h>

#include <cmath>

#include "model_run.hpp"

namespace sear::test {
namespace {

TEST(RestingRover, AnUnpoweredRoverOnFlatGroundDoesNotCreep) {
  TempDir dir;
  // No MCU, no script: both motors coast, held only by their 0.02 N*m of gear friction.
  std::string project = rover_project("", "", 11.0);
  const auto run = run_sear(dir, project, "--trace-rate 1");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Trace trace(run.file("trace_rover.csv"));
  // From 1 s (it has dropped its 2 mm onto its wheels and caster by then) to 11 s.
  const Pose a = pose_at(trace, 1000000), b = pose_at(trace, 11000000);
  // A wheel held by a velocity row of force limit 0.02 N*m under the world's CFM of 1e-6 slips
  // at most CFM x torque / step = 2e-5 rad/s, 0.9 um/s at the 45 mm tyre: 9 um in 10 s, and the
  // trace's micrometre rounding adds under 1.5 um (5 um measured). The heading: the two wheels
  // slipping apart by 18 um over the 22 cm track, 8e-5 rad, so 1e-4.
  EXPECT_LT(std::hypot(b.p.x - a.p.x, b.p.y - a.p.y), 10.5e-6)
      << "from (" << a.p.x << ", " << a.p.y << ") to (" << b.p.x << ", " << b.p.y << ") m";
  EXPECT_LT(std::abs(b.yaw - a.yaw), 1e-4) << a.yaw << " -> " << b.yaw << " rad";
}

}  // namespace
}  // namespace sear::test
