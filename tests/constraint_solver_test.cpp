// Which of ODE's solvers takes a step (physics/constraint_solver): the direct one for a robot's
// group of bodies, the iterative one for a group too large for it and for a step it gives up on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "test_world.hpp"

namespace sear {
namespace {

// The rover on flat ground, driving at full duty, with `obstacles` in its world.
ProjectDesc rover_among(const std::string& obstacles) {
  return test::project_from_xml(test::project_xml(
      R"(step="0.001")", obstacles, R"(<robot file="../robots/rover.xml"><pose x="0" y="0" yaw_deg="0"/></robot>)"));
}

void drive_on(Simulation& sim) {
  test::drive(sim, "left", 1.0, MotorDirection::Forward);
  test::drive(sim, "right", 1.0, MotorDirection::Forward);
}

std::uint64_t steps(const ConstraintSolver::Counts& c) { return c.direct + c.iterative; }

// The rover's group: two hinges and two gear-friction rows (six rows each at most) and its two
// treads and caster on the ground (three a point): 33 rows, under the direct solver's 64. Nine
// 0.3 m crates side by side on the ground, kept awake, rest on at least four points each: 108.
TEST(ConstraintSolver, ARoverIsSolvedDirectlyAndAPileOfCratesIteratively) {
  Simulation alone(rover_among(""), 1);
  drive_on(alone);
  test::run_for(alone, 1.0);
  const ConstraintSolver::Counts& a = alone.physics().solver_counts();
  EXPECT_EQ(a.direct, steps(a));
  EXPECT_EQ(a.retaken, 0u);

  std::string crates;
  for (int i = 0; i < 9; ++i)
    crates += "<box name=\"crate" + std::to_string(i) + "\" pos=\"" + std::to_string(-3.0 + 0.3 * (i % 3)) + " " +
              std::to_string(3.0 + 0.3 * (i / 3)) + "\" size=\"0.3 0.3 0.3\" mass=\"0.5\"/>";
  Simulation piled(rover_among(crates), 1);
  const dSpaceID space = piled.physics().dynamic_space();
  for (int g = 0; g < dSpaceGetNumGeoms(space); ++g)
    if (dBodyID body = dGeomGetBody(dSpaceGetGeom(space, g))) dBodySetAutoDisableFlag(body, 0);
  drive_on(piled);
  test::run_for(piled, 1.0);
  const ConstraintSolver::Counts& p = piled.physics().solver_counts();
  EXPECT_EQ(p.iterative, steps(p));
  EXPECT_GT(piled.physics().contact_count(), 36u);
}

// Driven into a wall at its top speed, the rover meets it with its chassis' corners and the
// ground under its wheels at once: a set ODE's direct solver gives up on (a pivot with s <= 0),
// leaving the rows it had not reached without force. Those steps are taken again by the
// iterative solver from the state before them, and nothing is printed of it.
TEST(ConstraintSolver, AStepTheDirectSolverGivesUpOnIsTakenAgainIteratively) {
  ::testing::internal::CaptureStderr();
  const ProjectDesc project = rover_among(R"(<wall name="barrier" from="3 -2" to="3 2" height="0.5" thickness="0.01"/>)");
  Simulation sim(project, 1);
  drive_on(sim);
  // A step taken twice over, the second from where the first left the rover, would move it two
  // steps' way at once: no step may move it further than its free-running speed does (0.73 mm).
  const MotorDesc& m = project.robots[0].motors[0];
  const double top_speed = m.no_load_speed_radps * (1.0 - m.gear_friction_nm / m.stall_torque_nm) *
                           project.robots[0].wheels[0].radius_m;
  double x = sim.robot(0).state().position_m.x(), longest_step = 0;
  test::run_for(sim, 10.0, [&] {
    const double now = sim.robot(0).state().position_m.x();
    longest_step = std::max(longest_step, std::abs(now - x));
    x = now;
  });
  const std::string printed = ::testing::internal::GetCapturedStderr();
  const ConstraintSolver::Counts& c = sim.physics().solver_counts();
  EXPECT_GE(c.retaken, 1u);
  EXPECT_EQ(c.direct + c.retaken, steps(c));  // no group was too large
  EXPECT_EQ(printed.find("ODE Message"), std::string::npos) << printed;
  // It stopped at the wall (drive_test holds how exactly): the retaken steps left it whole.
  const VehicleState s = sim.robot(0).state();
  EXPECT_TRUE(std::isfinite(s.position_m.x()));
  EXPECT_LT(std::abs(s.forward_speed_mps), 0.01);
  EXPECT_NEAR(s.position_m.x(), 3.0 - 0.005 - 0.15, 0.01);
  // The supply is the rated voltage here (rover.xml), so full duty is the free-running speed;
  // 2 % for the chassis pitching as it sets off and stops.
  EXPECT_LT(longest_step, 1.02 * top_speed * 0.001);
}

// A 1 kg box sliding at 1 m/s on four friction contacts with no CFM at all (the project's
// contacts have some: a set the direct solver meets only now and then): ODE's direct solver gives
// up on its second step. Taken again, that step must be what the iterative solver makes of the
// state before it, to the bit: a twin world stepped so from the same state.
struct SlidingBox {
  dWorldID world = dWorldCreate();
  dSpaceID space = dSimpleSpaceCreate(nullptr);
  dJointGroupID contacts = dJointGroupCreate(0);
  dBodyID body = dBodyCreate(world);
  SlidingBox() {
    dWorldSetGravity(world, 0, 0, -9.81);
    dWorldSetCFM(world, 0);
    dMass mass;
    dMassSetBoxTotal(&mass, 1.0, 0.3, 0.3, 0.3);
    dBodySetMass(body, &mass);
    dBodySetPosition(body, 0, 0, 0.15);
    dBodySetLinearVel(body, 1, 0, 0);
    dGeomSetBody(dCreateBox(space, 0.3, 0.3, 0.3), body);
  }
  ~SlidingBox() {
    dJointGroupDestroy(contacts);
    dSpaceDestroy(space);
    dWorldDestroy(world);
  }
  void touch_ground() {
    dJointGroupEmpty(contacts);
    const dReal* p = dBodyGetPosition(body);
    for (int corner = 0; corner < 4; ++corner) {
      dContact c{};
      c.surface.mode = dContactApprox1 | dContactSoftCFM;
      c.surface.mu = 0.5;
      c.geom.pos[0] = p[0] + ((corner & 1) ? 0.15 : -0.15);
      c.geom.pos[1] = p[1] + ((corner & 2) ? 0.15 : -0.15);
      c.geom.normal[2] = 1;
      c.geom.depth = 1e-4;
      dJointAttach(dJointCreateContact(world, contacts, &c), body, nullptr);
    }
  }
};

TEST(ConstraintSolver, AStepTakenAgainStartsFromTheStateBeforeIt) {
  struct Ode {  // no Simulation here to set ODE up; the boxes go first
    Ode() { dInitODE2(0); }
    ~Ode() { dCloseODE(); }
  } ode;
  SlidingBox solved, twin;
  ConstraintSolver solver(true);
  for (SlidingBox* box : {&solved, &twin}) {
    box->touch_ground();
    dWorldStep(box->world, 0.001);  // the first step the direct solver takes
    box->touch_ground();
  }
  dRandSetSeed(1);  // the iterative solver's shuffle
  solver.step(solved.world, solved.space, 0.001);
  dRandSetSeed(1);
  dWorldQuickStep(twin.world, 0.001);
  ASSERT_EQ(solver.counts().retaken, 1u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(dBodyGetPosition(solved.body)[i], dBodyGetPosition(twin.body)[i]) << i;
    EXPECT_EQ(dBodyGetLinearVel(solved.body)[i], dBodyGetLinearVel(twin.body)[i]) << i;
    EXPECT_EQ(dBodyGetAngularVel(solved.body)[i], dBodyGetAngularVel(twin.body)[i]) << i;
  }
}

}  // namespace
}  // namespace sear
