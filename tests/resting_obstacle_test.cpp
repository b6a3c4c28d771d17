// Loose obstacles sleep once they rest (PhysicsWorld: ODE's auto-disable) and wake when touched:
// a rover driving into a resting crate pushes it as it would push one that never slept.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <string>

#include "test_world.hpp"

namespace sear {
namespace {

// A 0.8 kg, 0.3 m crate on flat ground 0.6 m ahead of the rover, on a slope-free grass world.
ProjectDesc crate_project() {
  return test::project_from_xml(test::project_xml(
      R"(step="0.001")", R"(<material name="wood" friction="0.5"/>
         <box name="crate" pos="0.6 0.02" size="0.3 0.3 0.3" mass="0.8" material="wood"/>)",
      R"(<robot file="../robots/rover.xml"><pose x="0" y="0" yaw_deg="0"/></robot>)"));
}

dBodyID body_of(const Simulation& sim, const std::string& name) {
  const PhysicsWorld& physics = sim.physics();
  const dSpaceID space = physics.dynamic_space();
  for (int i = 0; i < dSpaceGetNumGeoms(space); ++i) {
    dGeomID geom = dSpaceGetGeom(space, i);
    const auto* tag = static_cast<const GeomTag*>(dGeomGetData(geom));
    if (tag && tag->role == GeomRole::Obstacle && physics.entity_names()[static_cast<std::size_t>(tag->entity)] == name)
      return dGeomGetBody(geom);
  }
  return nullptr;
}

struct Push {
  Eigen::Vector3d crate_before, crate_after, rover_after;
  bool slept_before_contact;
};

// The rover stands for 0.5 s (the crate settles, and sleeps if it may), then drives at full duty
// for 2 s: it meets the crate after about 0.4 m and pushes it on.
Push push_crate(bool crate_may_sleep, std::uint64_t seed) {
  const ProjectDesc project = crate_project();
  Simulation sim(project, seed);
  dBodyID crate = body_of(sim, "crate");
  if (!crate) throw std::runtime_error("no crate body");
  if (!crate_may_sleep) dBodySetAutoDisableFlag(crate, 0);
  test::run_for(sim, 0.5);
  Push push;
  push.slept_before_contact = !dBodyIsEnabled(crate);
  const dReal* p = dBodyGetPosition(crate);
  push.crate_before = {p[0], p[1], p[2]};
  test::drive(sim, "left", 1.0, MotorDirection::Forward);
  test::drive(sim, "right", 1.0, MotorDirection::Forward);
  test::run_for(sim, 2.0);
  p = dBodyGetPosition(crate);
  push.crate_after = {p[0], p[1], p[2]};
  push.rover_after = sim.robot(0).state().position_m;
  return push;
}

TEST(RestingObstacle, ARobotPushesASleepingCrateAsOneThatNeverSlept) {
  const Push asleep = push_crate(true, 1);
  const Push awake = push_crate(false, 1);
  ASSERT_TRUE(asleep.slept_before_contact);  // else this test compares nothing
  ASSERT_FALSE(awake.slept_before_contact);
  // Both were pushed most of the rover's way, so the sleeper woke at the contact.
  EXPECT_GT(asleep.crate_after.x() - asleep.crate_before.x(), 0.6);
  EXPECT_GT(awake.crate_after.x() - awake.crate_before.x(), 0.6);

  // Sleeping froze the crate where it settled, within what the rest rule lets it still move: 1
  // cm/s averaged for 0.1 s, 1 mm. Pushed on from there, crate and rover end within that of the
  // never-sleeping crate's run (0.15 mm measured). A sleeper woken without its ground contacts in
  // the step it is first touched slides on air for that step: 1.9 mm.
  EXPECT_NEAR(asleep.crate_after.x(), awake.crate_after.x(), 1e-3);
  EXPECT_NEAR(asleep.rover_after.x(), awake.rover_after.x(), 1e-3);

  // Pushed, the crate rides on the rover's front face: its centre is the two half-lengths (0.15 m
  // each) ahead of the chassis centre, nearer by the contact's give (push force mu m g = 3.9 N times
  // step * CFM / ERP, about 0.1 um) and by the crate turning against the face: 0.15 (1 - cos a),
  // under 0.75 mm for a turn a under 0.1 rad. Sleeping must not change that by more than 1 mm.
  EXPECT_NEAR(asleep.crate_after.x() - asleep.rover_after.x(), 0.30, 1e-3);
  EXPECT_NEAR(asleep.crate_after.x() - asleep.rover_after.x(), awake.crate_after.x() - awake.rover_after.x(), 1e-3);
  // It set off 2 cm left of the rover's axis and slides sideways only as friction at the face
  // lets it: within 1 mm of the never-sleeping crate's sideways drift.
  EXPECT_NEAR(asleep.crate_after.y() - asleep.crate_before.y(), awake.crate_after.y() - awake.crate_before.y(), 1e-3);
  // Sleeping froze it where it settled: its height on the ground within the contact's give and
  // the creep allowed before sleep (1 cm/s averaged is not a sink; ODE's soft contact holds a
  // 0.8 kg box within micrometres), so 0.1 mm.
  EXPECT_NEAR(asleep.crate_before.z(), awake.crate_before.z(), 1e-4);
}

TEST(RestingObstacle, AFallingCrateDoesNotSleepInTheAir) {
  // A crate dropped from 0.5 m: a body in free fall is never still, so it lands as before.
  const ProjectDesc project = test::project_from_xml(test::project_xml(
      R"(step="0.001")", R"(<box name="crate" pos="0.6 0" z="0.5" size="0.3 0.3 0.3" mass="0.8"/>)", ""));
  Simulation sim(project, 1);
  dBodyID crate = body_of(sim, "crate");
  ASSERT_NE(crate, nullptr);
  double lowest = 1e9;
  test::run_for(sim, 0.5, [&] {
    lowest = std::min(lowest, dBodyGetPosition(crate)[2]);
    EXPECT_TRUE(dBodyIsEnabled(crate) || dBodyGetPosition(crate)[2] < 0.151);
  });
  // Free fall takes sqrt(2 * (0.5 - 0.15) / g) = 0.27 s to the ground; by 0.5 s it lies there, asleep.
  EXPECT_NEAR(dBodyGetPosition(crate)[2], 0.15, 1e-3);
  EXPECT_FALSE(dBodyIsEnabled(crate));
}

}  // namespace
}  // namespace sear
