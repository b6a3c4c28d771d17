// Free fall against z = z0 - g t^2 / 2, on a box dropped from 50 m in an otherwise empty world.
#include <gtest/gtest.h>

#include "physics/physics_world.hpp"
#include "physics/scenery.hpp"
#include "runtime/simulation.hpp"
#include "test_world.hpp"

namespace sear {
namespace {

TEST(FreeFall, FollowsHalfGTSquaredWithinOnePercent) {
  const ProjectDesc project = test::project_from_xml(test::project_xml(
      R"(gravity="0 0 -9.81" step="0.001")", R"(<box name="dropped" pos="0 0" z="50" size="0.2 0.2 0.2" mass="1"/>)", ""));
  PhysicsWorld physics(project.world, 1);
  build_terrain(physics, project.world.terrain);
  ASSERT_TRUE(build_obstacles(physics, project.world, project.file).empty());
  ASSERT_EQ(dSpaceGetNumGeoms(physics.dynamic_space()), 1);
  dBodyID body = dGeomGetBody(dSpaceGetGeom(physics.dynamic_space(), 0));
  ASSERT_NE(body, nullptr);

  constexpr double g = 9.81, z0 = 50.0;
  for (int step = 1; step <= 3000; ++step) {
    physics.step();
    if (step % 500 != 0) continue;
    const double t = step * 1e-3;
    const double expected_drop = 0.5 * g * t * t;  // 44.1 m at 3 s: still in the air
    const double drop = z0 - dBodyGetPosition(body)[2];
    EXPECT_NEAR(drop, expected_drop, 0.01 * expected_drop) << "t = " << t;
    // Exactly what ODE's semi-implicit Euler integrates: v_n = -g h n, z_n = z0 - g h^2 n (n + 1) / 2.
    const double n = step, h = 1e-3;
    EXPECT_NEAR(drop, g * h * h * n * (n + 1) / 2, 1e-9 * expected_drop) << "t = " << t;
    EXPECT_NEAR(dBodyGetLinearVel(body)[2], -g * t, 0.01 * g * t) << "t = " << t;
    EXPECT_NEAR(dBodyGetPosition(body)[0], 0.0, 1e-12);  // nothing pushes it sideways
  }
}

// The whole simulation steps with the world's own step, from the project file through the
// loader to ODE: after n steps of h = 2 ms (not the default 1 ms) the clock reads n h and a box let
// go 50 m up has dropped exactly g h^2 n (n + 1) / 2 (at 0.1 s, 0.49 mm more than with 1 ms steps).
TEST(FreeFall, TheSimulationStepsWithTheWorldsOwnStep) {
  const ProjectDesc project = test::project_from_xml(test::project_xml(
      R"(gravity="0 0 -9.81" step="0.002")", R"(<box name="dropped" pos="0 0" z="50" size="0.2 0.2 0.2" mass="1"/>)", ""));
  Simulation sim(project, 1);
  EXPECT_EQ(sim.step_ns(), 2'000'000);
  ASSERT_EQ(dSpaceGetNumGeoms(sim.physics().dynamic_space()), 1);
  dBodyID body = dGeomGetBody(dSpaceGetGeom(sim.physics().dynamic_space(), 0));
  ASSERT_NE(body, nullptr);
  const double z0 = dBodyGetPosition(body)[2], g = 9.81, h = 0.002;
  for (int n = 1; n <= 50; ++n) sim.step();
  EXPECT_EQ(sim.time_ns(), 100'000'000);
  const double n = 50;
  EXPECT_NEAR(z0 - dBodyGetPosition(body)[2], g * h * h * n * (n + 1) / 2, 1e-9);
}

}  // namespace
}  // namespace sear
