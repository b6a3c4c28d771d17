// The actuator models on their own, against the relations that define them.
#include <gtest/gtest.h>

#include <cmath>

#include "physics/ackermann.hpp"
#include "physics/dc_motor.hpp"
#include "physics/servo.hpp"

namespace sear {
namespace {

MotorDesc gearmotor() {
  MotorDesc m;
  m.stall_torque_nm = 0.6;
  m.no_load_speed_radps = 160 * 2 * M_PI / 60;  // 160 rpm
  m.rated_voltage_v = 6;
  m.supply_voltage_v = 6;
  return m;
}

TEST(DcMotor, TorqueSpeedLineRunsFromStallToNoLoad) {
  const MotorDesc m = gearmotor();
  EXPECT_DOUBLE_EQ(dc_motor_torque(m, {1.0, MotorDirection::Forward}, 0.0), 0.6);
  EXPECT_NEAR(dc_motor_torque(m, {1.0, MotorDirection::Forward}, m.no_load_speed_radps), 0.0, 1e-12);
  EXPECT_NEAR(dc_motor_torque(m, {1.0, MotorDirection::Forward}, 0.5 * m.no_load_speed_radps), 0.3, 1e-12);
  // Half duty averages to half the voltage: half the stall torque, half the free speed.
  EXPECT_DOUBLE_EQ(dc_motor_torque(m, {0.5, MotorDirection::Forward}, 0.0), 0.3);
  EXPECT_NEAR(dc_motor_torque(m, {0.5, MotorDirection::Forward}, 0.5 * m.no_load_speed_radps), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(dc_motor_torque(m, {0.5, MotorDirection::Reverse}, 0.0), -0.3);
}

TEST(DcMotor, BrakeOpposesMotionAndCoastDoesNot) {
  const MotorDesc m = gearmotor();
  const double omega = 10.0;
  // Shorted winding: back-EMF drives a current that brakes with the line's slope, stall / free speed.
  EXPECT_NEAR(dc_motor_torque(m, {0.0, MotorDirection::Brake}, omega), -0.6 / m.no_load_speed_radps * omega, 1e-12);
  EXPECT_NEAR(dc_motor_torque(m, {0.0, MotorDirection::Brake}, -omega), 0.6 / m.no_load_speed_radps * omega, 1e-12);
  EXPECT_EQ(dc_motor_torque(m, {0.0, MotorDirection::Coast}, omega), 0.0);
  EXPECT_EQ(dc_motor_torque(m, {1.0, MotorDirection::Coast}, omega), 0.0);  // duty means nothing with the bridge open
}

TEST(DcMotor, StallTorqueAndFreeSpeedScaleWithSupplyVoltage) {
  MotorDesc m = gearmotor();
  m.supply_voltage_v = 9;  // a 6 V motor run from 9 V
  EXPECT_DOUBLE_EQ(dc_motor_torque(m, {1.0, MotorDirection::Forward}, 0.0), 0.9);
  EXPECT_NEAR(dc_motor_torque(m, {1.0, MotorDirection::Forward}, 1.5 * m.no_load_speed_radps), 0.0, 1e-12);
  EXPECT_NEAR(dc_motor_steady_speed(m, 1.0, 0.0), 1.5 * m.no_load_speed_radps, 1e-9);
  // A load of a third of the rated stall torque costs a third of the rated free speed.
  EXPECT_NEAR(dc_motor_steady_speed(gearmotor(), 1.0, 0.2), 2.0 / 3.0 * m.no_load_speed_radps, 1e-9);
  EXPECT_EQ(dc_motor_steady_speed(gearmotor(), 0.1, 0.2), 0.0);  // too weak to overcome the load
}

ServoDesc standard_servo() {
  ServoDesc s;
  s.min_pulse_us = 1000;
  s.max_pulse_us = 2000;
  s.range_rad = 60 * M_PI / 180;
  s.speed_radps = (60 * M_PI / 180) / 0.17;  // 0.17 s per 60 degrees
  return s;
}

TEST(Servo, PulseWidthMapsLinearlyOntoTravel) {
  const ServoDesc s = standard_servo();
  EXPECT_DOUBLE_EQ(servo_target_angle(s, 1500), 0.0);
  EXPECT_NEAR(servo_target_angle(s, 2000), 30 * M_PI / 180, 1e-12);
  EXPECT_NEAR(servo_target_angle(s, 1000), -30 * M_PI / 180, 1e-12);
  EXPECT_NEAR(servo_target_angle(s, 1250), -15 * M_PI / 180, 1e-12);
  EXPECT_NEAR(servo_target_angle(s, 2500), 30 * M_PI / 180, 1e-12);  // beyond the range: held at the end stop
}

TEST(Servo, SweepsSixtyDegreesInItsRatedTime) {
  const ServoDesc s = standard_servo();
  const double dt = 0.001;
  double angle = servo_target_angle(s, 1000);
  int steps = 0;
  while (angle < servo_target_angle(s, 2000) - 1e-12) {
    angle = servo_slew(s, angle, servo_target_angle(s, 2000), dt);
    ++steps;
  }
  EXPECT_NEAR(steps * dt, 0.17, dt);
}

TEST(Servo, ContinuousSpeedFollowsPulseOffset) {
  ServoDesc s = standard_servo();
  s.kind = ServoDesc::Kind::Continuous;
  s.speed_radps = 50 * 2 * M_PI / 60;
  EXPECT_DOUBLE_EQ(servo_target_speed(s, 1500), 0.0);
  EXPECT_NEAR(servo_target_speed(s, 2000), s.speed_radps, 1e-12);
  EXPECT_NEAR(servo_target_speed(s, 1300), -0.4 * s.speed_radps, 1e-12);
}

TEST(Ackermann, BothWheelsTurnAboutOneCentreOnTheRearAxleLine) {
  const double wheelbase = 0.26, half_track = 0.10;
  for (double steer_deg : {5.0, 15.0, 30.0, -20.0}) {
    const double steer = steer_deg * M_PI / 180;
    const double left = ackermann_wheel_angle(steer, wheelbase, half_track);
    const double right = ackermann_wheel_angle(steer, wheelbase, -half_track);
    // The normal to a wheel at (L, y) steered by a meets the rear axle line (x = 0) at y + L / tan a;
    // the virtual centre wheel's meets it at L / tan(steer).
    const double centre = wheelbase / std::tan(steer);
    EXPECT_NEAR(half_track + wheelbase / std::tan(left), centre, 1e-9) << steer_deg;
    EXPECT_NEAR(-half_track + wheelbase / std::tan(right), centre, 1e-9) << steer_deg;
    // The inner wheel (left in a left turn) turns more than the outer.
    const double inner = steer > 0 ? left : right, outer = steer > 0 ? right : left;
    EXPECT_GT(std::abs(inner), std::abs(outer)) << steer_deg;
  }
  EXPECT_EQ(ackermann_wheel_angle(0.0, wheelbase, half_track), 0.0);
}

}  // namespace
}  // namespace sear
