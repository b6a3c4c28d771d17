// Fast wheels: at 3000 rpm a wheel turns 0.31 rad per 1 ms step; its joint must hold and the
// robot's angular momentum must be kept. (Wheels also use ODE's finite rotation mode about the
// axle, as ODE's manual advises for wheels; at this speed ODE's default integration passes too,
// so this test guards the outcome, not that setting.)
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "test_world.hpp"

namespace sear {
namespace {

Eigen::Vector3d vec(const dReal* v) { return {v[0], v[1], v[2]}; }

Eigen::Matrix3d rotation(dBodyID body) {
  const dReal* r = dBodyGetRotation(body);
  Eigen::Matrix3d m;
  m << r[0], r[1], r[2], r[4], r[5], r[6], r[8], r[9], r[10];
  return m;
}

double mass_of(dBodyID body) {
  dMass mass;
  dBodyGetMass(body, &mass);
  return mass.mass;
}

// Angular momentum of bodies about their common centre of mass: sum of R I R^T w + m (p - c) x (v - v_c).
Eigen::Vector3d angular_momentum(const std::vector<dBodyID>& bodies) {
  double total_mass = 0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero(), vc = Eigen::Vector3d::Zero();
  for (dBodyID b : bodies) {
    total_mass += mass_of(b);
    c += mass_of(b) * vec(dBodyGetPosition(b));
    vc += mass_of(b) * vec(dBodyGetLinearVel(b));
  }
  c /= total_mass;
  vc /= total_mass;
  Eigen::Vector3d l = Eigen::Vector3d::Zero();
  for (dBodyID b : bodies) {
    dMass mass;
    dBodyGetMass(b, &mass);
    Eigen::Matrix3d inertia;
    inertia << mass.I[0], mass.I[1], mass.I[2], mass.I[4], mass.I[5], mass.I[6], mass.I[8], mass.I[9], mass.I[10];
    const Eigen::Matrix3d r = rotation(b);
    l += r * inertia * r.transpose() * vec(dBodyGetAngularVel(b)) +
         mass.mass * (vec(dBodyGetPosition(b)) - c).cross(vec(dBodyGetLinearVel(b)) - vc);
  }
  return l;
}

TEST(FastWheels, SpinAt3000RpmInFreeSpaceWithTheJointsHeldAndMomentumKept) {
  // Gravity pointing up carries the robot clear of the ground before its counter-rotating chassis
  // could touch it; uniform gravity exerts no torque about the centre of mass, so only the
  // motors turn anything, and they are an internal pair.
  const ProjectDesc project = test::project_from_xml(test::project_xml(R"(gravity="0 0 5" step="0.001")", "", R"(
  <robot name="fast" drive="differential">
    <chassis shape="box" size="0.30 0.18 0.06" mass="1.5" material="plastic"/>
    <wheel name="left" pos="0.04 0.11 -0.01" radius="0.045" width="0.025" mass="0.06" material="rubber"/>
    <wheel name="right" pos="0.04 -0.11 -0.01" radius="0.045" width="0.025" mass="0.06" material="rubber"/>
    <caster pos="-0.11 0 -0.035" radius="0.02"/>
    <motor name="left" wheels="left" stall_torque="0.05" no_load_rpm="3000"/>
    <motor name="right" wheels="right" stall_torque="0.05" no_load_rpm="3000"/>
  </robot>)"));
  Simulation sim(project, 1);
  Vehicle& v = sim.robot(0);
  test::drive(sim, "left", 1.0, MotorDirection::Forward);
  test::drive(sim, "right", 1.0, MotorDirection::Forward);

  const double free_speed = 3000 * 2 * M_PI / 60;  // 314 rad/s
  double worst_anchor_m = 0, worst_axle_rad = 0;
  const double start_z = vec(dBodyGetPosition(v.chassis_body())).z();
  double lowest_z = start_z;
  test::run_for(sim, 3.0, [&] {
    const Eigen::Matrix3d chassis = rotation(v.chassis_body());
    const Eigen::Vector3d origin = vec(dBodyGetPosition(v.chassis_body()));
    lowest_z = std::min(lowest_z, origin.z());
    for (std::size_t w = 0; w < 2; ++w) {
      const Eigen::Vector3d anchor = origin + chassis * project.robots[0].wheels[w].position_m;
      worst_anchor_m = std::max(worst_anchor_m, (vec(dBodyGetPosition(v.wheel_body(w))) - anchor).norm());
      const Eigen::Vector3d axle = rotation(v.wheel_body(w)).col(2);
      worst_axle_rad = std::max(worst_axle_rad, std::acos(std::min(1.0, axle.dot(chassis.col(1)))));
    }
  });
  // Unloaded in free space, each wheel reaches its motor's free speed relative to the chassis.
  EXPECT_NEAR(v.wheel_speed(0), free_speed, 0.02 * free_speed);
  EXPECT_NEAR(v.wheel_speed(1), free_speed, 0.02 * free_speed);
  EXPECT_LT(worst_anchor_m, 1e-4);
  EXPECT_LT(worst_axle_rad, 0.5 * M_PI / 180);

  // The robot's total angular momentum stays what it was, zero, the chassis turning backwards as
  // the wheels spin up. Compare with one wheel's own momentum.
  EXPECT_GE(lowest_z, start_z);  // it never came down onto the ground
  EXPECT_GT(vec(dBodyGetPosition(v.chassis_body())).z(), 20.0);  // 5 m/s^2 for 3 s: 22.5 m up
  const Eigen::Vector3d total = angular_momentum({v.chassis_body(), v.wheel_body(0), v.wheel_body(1)});
  const double one_wheel = 0.5 * 0.06 * 0.045 * 0.045 * free_speed;  // (m r^2 / 2) w of a solid disc
  EXPECT_LT(total.norm(), 0.01 * one_wheel);
  EXPECT_LT(vec(dBodyGetAngularVel(v.chassis_body())).dot(rotation(v.chassis_body()).col(1)), 0.0);
}

}  // namespace
}  // namespace sear
