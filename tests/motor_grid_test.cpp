// DC gearmotors across the whole range a hobbyist buys, from 0.05 to 300 N*m stall and 5 to
// 20 000 rpm free speed, on the bundled rover's 60 g wheels: each motor must stay stable at the
// 1 ms step however strong and slow it is against the wheel's inertia.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "physics/dc_motor.hpp"
#include "test_world.hpp"

namespace sear {
namespace {

constexpr double kRpm = 2 * M_PI / 60;
const std::vector<double> kStallTorques_nm = {0.05, 0.5, 5, 50, 300};
const std::vector<double> kFreeSpeeds_rpm = {5, 50, 500, 5000, 20000};

// The rover with both motors replaced; the loader's own limits are not what is tested here.
ProjectDesc rover_with(double stall_nm, double rpm, const std::string& gravity) {
  ProjectDesc p = test::project_from_xml(test::project_xml(
      "step=\"0.001\" gravity=\"" + gravity + "\"", "",
      R"(<robot file="../robots/rover.xml"><pose x="0" y="0" yaw_deg="0"/></robot>)"));
  for (auto& m : p.robots[0].motors) {
    m.stall_torque_nm = stall_nm;
    m.no_load_speed_radps = rpm * kRpm;
  }
  return p;
}

bool finite(const Simulation& sim) {
  const Vehicle& v = sim.robot(0);
  std::vector<dBodyID> bodies{v.chassis_body()};
  for (std::size_t w = 0; w < v.wheel_count(); ++w) bodies.push_back(v.wheel_body(w));
  for (dBodyID b : bodies)
    for (const dReal* x : {dBodyGetPosition(b), dBodyGetLinearVel(b), dBodyGetAngularVel(b)})
      if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2])) return false;
  return true;
}

// Weight of every body times its height: the potential energy the robot can release.
double potential_energy(const Simulation& sim, double g) {
  const Vehicle& v = sim.robot(0);
  std::vector<dBodyID> bodies{v.chassis_body()};
  for (std::size_t w = 0; w < v.wheel_count(); ++w) bodies.push_back(v.wheel_body(w));
  double e = 0;
  for (dBodyID b : bodies) {
    dMass m;
    dBodyGetMass(b, &m);
    e += m.mass * g * dBodyGetPosition(b)[2];
  }
  return e;
}

// The form the physics applies, damping * (target - omega), is the datasheet's line: stall
// torque at standstill, none at the free speed, both scaled by supply / rated voltage.
TEST(MotorGrid, DriveFormIsTheTorqueSpeedLine) {
  MotorDesc m;
  m.stall_torque_nm = 5;
  m.no_load_speed_radps = 20 * kRpm;
  m.rated_voltage_v = 6;
  m.supply_voltage_v = 9;
  const DcMotorDrive forward = dc_motor_drive(m, {0.5, MotorDirection::Forward});
  EXPECT_TRUE(forward.engaged);
  EXPECT_NEAR(forward.damping_nmps, 5 / (20 * kRpm), 1e-12);
  EXPECT_NEAR(forward.target_radps, 0.5 * 1.5 * 20 * kRpm, 1e-12);
  EXPECT_NEAR(forward.damping_nmps * forward.target_radps, 0.5 * 1.5 * 5, 1e-12);  // half duty's stall torque
  EXPECT_NEAR(dc_motor_drive(m, {1.0, MotorDirection::Reverse}).target_radps, -1.5 * 20 * kRpm, 1e-12);
  EXPECT_EQ(dc_motor_drive(m, {1.0, MotorDirection::Brake}).target_radps, 0.0);
  EXPECT_TRUE(dc_motor_drive(m, {1.0, MotorDirection::Brake}).engaged);
  EXPECT_FALSE(dc_motor_drive(m, {1.0, MotorDirection::Coast}).engaged);
}

// Unpowered on level ground: duty 0 (the H-bridge shorts the winding, as the firmware leaves it),
// brake, and coast. Nothing drives the rover; it only settles from its spawn height. While it
// rolls, each wheel's gearbox friction F costs F / r of push, so over a distance d the two take
// 2 F d / r of work, which cannot exceed the potential energy it released settling: d <= E r / 2F.
// (Its wheels roll rather than skid: 0.8 of the ~5 N on each wheel holds far more than F / r = 0.44 N.)
// The motor's damping only adds to the braking. The chassis origin also shifts as it pitches onto
// its caster: 2 mm over the 15 cm to the caster turns it by 0.013 rad, moving the origin 1 cm
// above the axle line by 0.13 mm; 1 mm covers it. Today's explicit back-EMF drove this rover
// 10 m with a 5 N*m, 20 rpm motor.
TEST(MotorGrid, UnpoweredRoverStaysWhereItWasPut) {
  const double g = 9.81;
  for (double stall : kStallTorques_nm)
    for (double rpm : kFreeSpeeds_rpm)
      for (MotorDirection how : {MotorDirection::Forward, MotorDirection::Brake, MotorDirection::Coast}) {
        SCOPED_TRACE(::testing::Message() << stall << " N*m, " << rpm << " rpm, mode " << static_cast<int>(how));
        const ProjectDesc project = rover_with(stall, rpm, "0 0 -9.81");
        Simulation sim(project, 1);
        test::drive(sim, "left", 0.0, how);
        test::drive(sim, "right", 0.0, how);
        const Eigen::Vector3d start = sim.robot(0).state().position_m;
        const double e0 = potential_energy(sim, g);
        double fastest_wheel = 0;
        bool ok = true;
        test::run_for(sim, 2.0, [&] {
          ok = ok && finite(sim);
          for (std::size_t w = 0; w < 2; ++w) fastest_wheel = std::max(fastest_wheel, std::abs(sim.robot(0).wheel_speed(w)));
        });
        ASSERT_TRUE(ok);
        const MotorDesc& m = project.robots[0].motors[0];
        const double released = e0 - potential_energy(sim, g);
        const double r = project.robots[0].wheels[0].radius_m;
        const double bound = released * r / (2 * m.gear_friction_nm) + 0.001;
        const Eigen::Vector3d end = sim.robot(0).state().position_m;
        EXPECT_LT((end - start).head<2>().norm(), bound);
        // Nothing adds energy, so neither the wheel nor the chassis can turn faster than if all
        // the released energy were its own kinetic energy about the axle: |omega_rel| <=
        // sqrt(2E / I_wheel) + sqrt(2E / I_chassis). (A wheel at today's -123 rad/s holds 0.46 J.)
        dMass wheel_mass, chassis_mass;
        dBodyGetMass(sim.robot(0).wheel_body(0), &wheel_mass);
        dBodyGetMass(sim.robot(0).chassis_body(), &chassis_mass);
        const double wheel_inertia = 0.5 * wheel_mass.mass * r * r;  // a disc about its axle
        const double chassis_inertia = chassis_mass.I[5];            // about the chassis' y axis, the axle's
        EXPECT_LT(fastest_wheel, std::sqrt(2 * released / wheel_inertia) + std::sqrt(2 * released / chassis_inertia));
      }
}

// In free space (gravity pointing up carries the rover clear of the ground) the wheels' only
// load is their gearbox friction: full forward, each settles where the torque line meets it,
// omega_free * (1 - F / stall), and on the way it never passes that speed, since the motor's
// torque reverses there and friction only slows it.
TEST(MotorGrid, FullForwardWheelReachesItsFreeRunningSpeedInFreeSpace) {
  for (double stall : kStallTorques_nm)
    for (double rpm : kFreeSpeeds_rpm) {
      SCOPED_TRACE(::testing::Message() << stall << " N*m, " << rpm << " rpm");
      const ProjectDesc project = rover_with(stall, rpm, "0 0 5");
      Simulation sim(project, 1);
      test::drive(sim, "left", 1.0, MotorDirection::Forward);
      test::drive(sim, "right", 1.0, MotorDirection::Forward);
      const MotorDesc& m = project.robots[0].motors[0];
      const WheelDesc& wheel = project.robots[0].wheels[0];
      const double k = m.stall_torque_nm / m.no_load_speed_radps;
      const double inertia = 0.5 * wheel.mass_kg * wheel.radius_m * wheel.radius_m;
      const double tau = inertia / k;  // the wheel's time constant against the motor's damping
      const double expected = m.no_load_speed_radps * (1 - m.gear_friction_nm / m.stall_torque_nm);
      double fastest = 0;
      bool ok = true;
      test::run_for(sim, std::max(0.2, 10 * tau), [&] {
        ok = ok && finite(sim);
        for (std::size_t w = 0; w < 2; ++w) fastest = std::max(fastest, std::abs(sim.robot(0).wheel_speed(w)));
      });
      ASSERT_TRUE(ok);
      // After ten time constants the approach has closed to e^-10 = 5e-5 of the way; the joint
      // row is solved to about that too (measured 4e-5 at the slowest, 0.05 N*m at 20 000 rpm).
      for (std::size_t w = 0; w < 2; ++w) EXPECT_NEAR(sim.robot(0).wheel_speed(w), expected, 1e-4 * expected);
      EXPECT_LT(fastest, expected * (1 + 1e-4));
    }
}

// Full forward on the ground, after the rover settled: the strongest and fastest motors spin
// it out on its slipping wheels, but nothing may turn non-finite or sink into the ground. While
// its chassis stays steady (turning under 1 rad/s) a wheel, driven by its motor alone, turns
// relative to the chassis no faster than its free speed plus the chassis' own turn rate (by
// which the chassis can turn under a wheel the ground holds). Slack for the solver, enough for
// the iterative one too, which the direct default beats: at 20 sweeps it leaves contacts creeping
// by about 1 mm/s (terrain_test), 2 mm/s / r here, and the motor row fighting a slipping contact
// converged to about 1e-3 of its target (0.9e-3 at 300 N*m, 500 rpm). Once the chassis whirls,
// the ground can spin a wheel as it likes.
TEST(MotorGrid, FullForwardOnTheGroundStaysFiniteAndUnderFreeSpeed) {
  for (double stall : kStallTorques_nm)
    for (double rpm : kFreeSpeeds_rpm) {
      SCOPED_TRACE(::testing::Message() << stall << " N*m, " << rpm << " rpm");
      const ProjectDesc project = rover_with(stall, rpm, "0 0 -9.81");
      Simulation sim(project, 1);
      test::run_for(sim, 0.5);
      test::drive(sim, "left", 1.0, MotorDirection::Forward);
      test::drive(sim, "right", 1.0, MotorDirection::Forward);
      const MotorDesc& m = project.robots[0].motors[0];
      const double slack = 0.002 / project.robots[0].wheels[0].radius_m + 1e-3 * m.no_load_speed_radps;
      double worst_excess = -1e9, lowest = 1e9;
      bool ok = true, steady = true;
      test::run_for(sim, 2.0, [&] {
        ok = ok && finite(sim);
        const VehicleState s = sim.robot(0).state();
        lowest = std::min(lowest, s.position_m.z());
        steady = steady && s.angular_velocity.norm() < 1.0;
        if (!steady) return;
        for (std::size_t w = 0; w < 2; ++w)
          worst_excess = std::max(worst_excess, std::abs(sim.robot(0).wheel_speed(w)) - m.no_load_speed_radps - s.angular_velocity.norm());
      });
      ASSERT_TRUE(ok);
      EXPECT_LT(worst_excess, slack);
      // Its chassis origin rides a wheel radius less 1 cm above the ground, give or take its tilt.
      EXPECT_GT(lowest, 0.0);
      EXPECT_TRUE(sim.robot_events().empty() || sim.robot_events()[0].kind == RobotEventKind::UpsideDown);
    }
}

// One motor behind an open differential turns at the mean of its wheels' speeds and gives each
// half its torque. Hold one rear wheel of the car fast to its chassis (in free space, gravity
// up, so only the motor and gearbox act) and the other must reach twice the free-running speed:
// its half of k (target - (0 + omega) / 2) balances its half of the friction F where omega =
// 2 (target - F / k). Wheels each on their own motor would stop at target - F / k.
TEST(MotorGrid, OpenDifferentialSpinsTheFreeWheelAtTwiceTheSpeed) {
  const ProjectDesc project = test::project_from_xml(test::project_xml(
      R"(step="0.001" gravity="0 0 5")", "", R"(<robot file="../robots/car.xml"><pose x="0" y="0"/></robot>)"));
  Simulation sim(project, 1);
  const RobotDesc& car = project.robots[0];
  ASSERT_EQ(car.wheels[2].name, "rear_left");
  ASSERT_EQ(car.wheels[3].name, "rear_right");
  dJointID hold = dJointCreateFixed(sim.physics().world(), nullptr);
  dJointAttach(hold, sim.robot(0).wheel_body(2), sim.robot(0).chassis_body());
  dJointSetFixed(hold);
  test::drive(sim, "drive", 1.0, MotorDirection::Forward);
  test::run_for(sim, 2.0);
  const MotorDesc& m = car.motors[0];
  const double k = m.stall_torque_nm / m.no_load_speed_radps;
  const double expected = 2 * (m.no_load_speed_radps - m.gear_friction_nm / k);
  // 2 s is two hundred of the free wheel's time constants (I / (k / 4) = 11 ms): only the
  // solver's residual is left, under 1e-4 as in the free-space grid above.
  EXPECT_NEAR(sim.robot(0).wheel_speed(2), 0.0, 1e-4 * expected);
  EXPECT_NEAR(sim.robot(0).wheel_speed(3), expected, 1e-4 * expected);
}

}  // namespace
}  // namespace sear
