// Driving on flat ground, checked against the motor model, rolling kinematics and geometry.
#include <gtest/gtest.h>

#include <cmath>

#include "test_world.hpp"

namespace sear {
namespace {

constexpr double kDeg = M_PI / 180.0;

std::string flat_world_with(const std::string& robot_file, const std::string& obstacles = "",
                            const std::string& pose = R"(<pose x="0" y="0" yaw_deg="0"/>)") {
  return test::project_xml(R"(step="0.001")", obstacles,
                           R"(<robot file="../robots/)" + robot_file + R"(">)" + pose + "</robot>");
}

double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }

// Where a DC gearmotor's torque line, stall * duty * V/V_rated - (stall / free speed) * omega,
// meets a constant load (its own gear friction on level ground): omega_free * (duty V/V_rated - load/stall).
double free_running_speed(const MotorDesc& m, double duty) {
  return m.no_load_speed_radps *
         (duty * m.supply_voltage_v / m.rated_voltage_v - m.gear_friction_nm / m.stall_torque_nm);
}

TEST(Drive, RoverReachesTheSteadySpeedOfItsMotorModel) {
  const ProjectDesc project = test::project_from_xml(flat_world_with("rover.xml"));
  Simulation sim(project, 1);
  const MotorDesc& motor = project.robots[0].motors[0];
  const double radius = project.robots[0].wheels[0].radius_m;
  for (double duty : {0.4, 0.7, 1.0}) {
    test::drive(sim, "left", duty, MotorDirection::Forward);
    test::drive(sim, "right", duty, MotorDirection::Forward);
    test::run_for(sim, 4.0);
    // On level ground the only load is the gearbox's own friction: torque balance gives the speed.
    const double expected = free_running_speed(motor, duty) * radius;
    EXPECT_GT(expected, 0.2);
    EXPECT_NEAR(sim.robot(0).state().forward_speed_mps, expected, 0.05 * expected) << "duty " << duty;
  }
}

TEST(Drive, EqualDutyDrivesStraight) {
  const ProjectDesc project = test::project_from_xml(flat_world_with("rover.xml"));
  Simulation sim(project, 1);
  test::drive(sim, "left", 1.0, MotorDirection::Forward);
  test::drive(sim, "right", 1.0, MotorDirection::Forward);
  while (sim.robot(0).state().position_m.x() < 10.0 && sim.time_s() < 30) sim.step();
  const VehicleState s = sim.robot(0).state();
  ASSERT_GE(s.position_m.x(), 10.0);
  EXPECT_LT(std::abs(s.roll_pitch_yaw.z()), 1.0 * kDeg);
  EXPECT_LT(std::abs(s.position_m.y()), 10.0 * std::tan(1.0 * kDeg));
}

TEST(Drive, OppositeDutyTurnsInPlace) {
  const ProjectDesc project = test::project_from_xml(flat_world_with("rover.xml"));
  Simulation sim(project, 1);
  const RobotDesc& rover = project.robots[0];
  const double duty = 0.5;
  test::drive(sim, "left", duty, MotorDirection::Reverse);
  test::drive(sim, "right", duty, MotorDirection::Forward);
  test::run_for(sim, 2.0);
  const VehicleState s = sim.robot(0).state();
  // The axle's midpoint is the pivot: the chassis origin, 4 cm behind it, only circles it.
  const double axle_offset = rover.wheels[0].position_m.x();
  EXPECT_LT(std::hypot(s.position_m.x(), s.position_m.y()), 2 * axle_offset + 0.01);
  // Pure rolling: yaw rate = (v_right - v_left) / track from the wheels' own speeds.
  const double track = rover.wheels[0].position_m.y() - rover.wheels[1].position_m.y();
  const double left = sim.robot(0).wheel_speed(0), right = sim.robot(0).wheel_speed(1);
  const double kinematic_yaw_rate = (right - left) * rover.wheels[0].radius_m / track;
  EXPECT_NEAR(s.angular_velocity.z(), kinematic_yaw_rate, 0.05 * kinematic_yaw_rate);
  EXPECT_LT(left, 0);
  EXPECT_GT(right, 0);
  // The centre of mass sits behind the axle, so spinning needs a centripetal push that loads
  // the motors: together they turn a little slower than free-running, never faster.
  const double free_running = free_running_speed(rover.motors[0], duty);
  EXPECT_LT(right - left, 2 * free_running);
  EXPECT_GT(right - left, 0.85 * 2 * free_running);
}

// At its top speed the rover moves 0.73 mm a step: a wall as thin as 1 cm must still stop it.
TEST(Drive, WallStopsTheRoverAtTopSpeed) {
  for (double thickness : {0.1, 0.01}) {
    const ProjectDesc project = test::project_from_xml(flat_world_with(
        "rover.xml", R"(<wall name="barrier" from="3 -2" to="3 2" height="0.5" thickness=")" +
                         std::to_string(thickness) + R"("/>)"));
    Simulation sim(project, 1);
    test::drive(sim, "left", 1.0, MotorDirection::Forward);
    test::drive(sim, "right", 1.0, MotorDirection::Forward);
    const RobotDesc& rover = project.robots[0];
    const double top_speed = free_running_speed(rover.motors[0], 1.0) * rover.wheels[0].radius_m;
    const double face = 3.0 - 0.5 * thickness;
    const double half_length = 0.5 * rover.chassis.size_m.x();
    double impact_speed = 0, furthest_front = -1e9;
    test::run_for(sim, 10.0, [&] {
      const VehicleState s = sim.robot(0).state();
      furthest_front = std::max(furthest_front, s.position_m.x() + half_length);
      if (sim.collisions().empty()) impact_speed = s.forward_speed_mps;
    });
    SCOPED_TRACE("wall thickness " + std::to_string(thickness));
    ASSERT_EQ(sim.collisions().size(), 1u);
    EXPECT_EQ(sim.collisions()[0].other, "barrier");
    EXPECT_NEAR(impact_speed, top_speed, 0.05 * top_speed);
    EXPECT_LT(furthest_front, face + 0.005);  // no tunnelling: at most contact softness into the wall
    EXPECT_GT(furthest_front, face - 0.005);  // and it really reached it
    EXPECT_LT(std::abs(sim.robot(0).state().forward_speed_mps), 0.01);
    EXPECT_LT(sim.robot(0).state().position_m.x(), 3.0);
  }
}

TEST(Drive, AckermannCarTurnsOnTheRadiusOfItsGeometry) {
  const ProjectDesc project = test::project_from_xml(flat_world_with("car.xml"));
  Simulation sim(project, 1);
  const RobotDesc& car = project.robots[0];
  Vehicle& v = sim.robot(0);
  v.command_servo(0, car.servos[0].max_pulse_us);  // full left: half the servo's travel
  test::drive(sim, "drive", 0.25, MotorDirection::Forward);
  test::run_for(sim, 5.0);
  const VehicleState s = v.state();
  const double wheelbase = car.wheels[0].position_m.x() - car.wheels[2].position_m.x();
  const double steer = 0.5 * car.servos[0].range_rad;
  // Bicycle model at low speed: the rear axle's centre turns on radius L / tan(steer).
  const double expected_radius = wheelbase / std::tan(steer);
  ASSERT_GT(s.forward_speed_mps, 0.1);
  EXPECT_GT(s.angular_velocity.z(), 0);  // left
  const double rear_axle_speed = s.forward_speed_mps;  // the chassis x axis is the rear axle's heading
  EXPECT_NEAR(rear_axle_speed / s.angular_velocity.z(), expected_radius, 0.1 * expected_radius);
}

TEST(Drive, SkidSteerDrivesStraightAndTurns) {
  const ProjectDesc project = test::project_from_xml(flat_world_with("skid4.xml"));
  Simulation sim(project, 1);
  const RobotDesc& robot = project.robots[0];
  test::drive(sim, "left", 0.8, MotorDirection::Forward);
  test::drive(sim, "right", 0.8, MotorDirection::Forward);
  test::run_for(sim, 3.0);
  VehicleState s = sim.robot(0).state();
  const double expected = free_running_speed(robot.motors[0], 0.8) * robot.wheels[0].radius_m;
  EXPECT_NEAR(s.forward_speed_mps, expected, 0.05 * expected);
  EXPECT_LT(std::abs(s.roll_pitch_yaw.z()), 1.0 * kDeg);
  // Opposite sides: it must skid its wheels sideways to turn, so it turns slower than rolling
  // kinematics would allow, but it turns left.
  const double yaw_before = s.roll_pitch_yaw.z();
  test::drive(sim, "left", 0.8, MotorDirection::Reverse);
  test::run_for(sim, 1.0);
  s = sim.robot(0).state();
  const double track = robot.wheels[0].position_m.y() - robot.wheels[2].position_m.y();
  const double rolling_yaw_rate = 2 * expected / track;
  EXPECT_GT(s.angular_velocity.z(), 0.1 * rolling_yaw_rate);
  EXPECT_LT(s.angular_velocity.z(), rolling_yaw_rate);
  EXPECT_GT(wrap(s.roll_pitch_yaw.z() - yaw_before), 0);
}

// A budget robot on two continuous-rotation servos: each wheel turns at the servo's speed for
// its pulse, so the robot drives at that speed times the wheel radius.
TEST(Drive, ContinuousServosDriveAtTheirPulseSpeed) {
  const ProjectDesc project = test::project_from_xml(test::project_xml(R"(step="0.001")", "", R"(
  <robot name="servobot" drive="differential">
    <chassis shape="box" size="0.15 0.12 0.05" mass="0.4" material="plastic"/>
    <wheel name="left" pos="0.03 0.075 -0.01" radius="0.033" width="0.01" mass="0.02" material="rubber"/>
    <wheel name="right" pos="0.03 -0.075 -0.01" radius="0.033" width="0.01" mass="0.02" material="rubber"/>
    <caster pos="-0.05 0 -0.033" radius="0.01"/>
    <servo name="left" kind="continuous" wheels="left" no_load_rpm="50" torque="0.3"/>
    <servo name="right" kind="continuous" wheels="right" no_load_rpm="50" torque="0.3"/>
    <script>
      <servo t="0" name="left" pulse_us="1800"/>
      <servo t="0" name="right" pulse_us="1800"/>
    </script>
  </robot>)"));
  Simulation sim(project, 1);
  test::run_for(sim, 2.0);
  const double wheel_speed = 0.6 * 50 * 2 * M_PI / 60;  // 300 us of the 500 us half-range above centre
  EXPECT_NEAR(sim.robot(0).wheel_speed(0), wheel_speed, 0.01 * wheel_speed);
  EXPECT_NEAR(sim.robot(0).state().forward_speed_mps, wheel_speed * 0.033, 0.03 * wheel_speed * 0.033);
}

}  // namespace
}  // namespace sear
