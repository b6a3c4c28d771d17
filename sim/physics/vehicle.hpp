// One robot in the ODE world: chassis, wheels on hinges (hinge-2 where steered), ball casters,
// and its actuators, DC motors and servos, which turn commands into joint torques each step.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <stdexcept>
#include <vector>

#include "physics/articulated_joint.hpp"
#include "physics/dc_motor.hpp"
#include "physics/physics_world.hpp"

namespace sear {

// A robot or obstacle that cannot be placed in the world, "file:line: error: ..." in what().
struct PlacementError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct VehicleState {
  Eigen::Vector3d position_m;        // chassis origin, world frame
  Eigen::Vector3d roll_pitch_yaw;    // rad, Z-Y-X Euler angles of the chassis
  Eigen::Vector3d velocity_mps;      // world frame
  Eigen::Vector3d angular_velocity;  // rad/s, world frame
  double forward_speed_mps;          // along the chassis x axis
};

class Vehicle {
 public:
  // Places the robot at its start pose, resting just above the terrain.
  Vehicle(PhysicsWorld& physics, const RobotDesc& desc);

  const RobotDesc& desc() const { return desc_; }
  int entity() const { return entity_; }

  int motor_index(const std::string& name) const;  // -1 when there is none
  int servo_index(const std::string& name) const;
  void command_motor(std::size_t motor, const DcMotorCommand& command) { motor_commands_[motor] = command; }
  // pulse_us 0: no pulses, the servo's output turns freely.
  void command_servo(std::size_t servo, double pulse_us) { servo_pulses_[servo] = pulse_us; }
  const DcMotorCommand& motor_command(std::size_t motor) const { return motor_commands_[motor]; }
  double servo_pulse(std::size_t servo) const { return servo_pulses_[servo]; }

  // Before each physics step: actuator torques and the wheels' finite-rotation axes.
  void apply_actuators(double dt_s);

  VehicleState state() const;
  // Spin of a wheel about its axle relative to the chassis, rad/s, positive rolling forward.
  double wheel_speed(std::size_t wheel) const;

  // Leaves the world: every body stops and sleeps, every geom stops colliding, the actuators
  // let go. For a robot that left the terrain or fell through it, so it falls no further.
  void freeze();
  bool frozen() const { return frozen_; }

  // The ODE bodies, for sensors that measure them and tests that check the joints.
  dBodyID chassis_body() const { return chassis_; }
  dBodyID wheel_body(std::size_t wheel) const { return wheels_[wheel].body; }
  std::size_t wheel_count() const { return wheels_.size(); }
  // A URDF's live joints (RobotDesc::joints), each with its link's body.
  const ArticulatedJoint& joint(std::size_t index) const { return joints_[index]; }
  std::size_t joint_count() const { return joints_.size(); }

 private:
  struct Wheel {
    dBodyID body;
    dJointID joint;
    bool steered;
    dJointID friction = nullptr;  // gearbox friction of a motor-driven wheel, if any
  };
  // The motor row of a wheel's joint: drive towards target_radps (the wheel relative to the
  // chassis, positive rolling forward) with at most max_torque_nm; 0 switches it off.
  static void set_drive(const Wheel& wheel, double target_radps, double max_torque_nm);
  // One of a URDF chassis' collision shapes, fixed to the chassis body.
  void add_part(PhysicsWorld& physics, const ShapeDesc& part, int material);
  Eigen::Vector3d axle_world(std::size_t wheel) const;
  std::size_t wheel_index(const std::string& name) const;

  RobotDesc desc_;
  int entity_;
  dBodyID chassis_;
  std::vector<Wheel> wheels_;
  std::vector<std::vector<std::size_t>> motor_wheels_;  // indices into wheels_, resolved once
  std::vector<std::vector<std::size_t>> servo_wheels_;
  std::vector<ArticulatedJoint> joints_;
  std::vector<int> servo_joint_;  // per servo: the live joint it turns, or -1
  std::vector<DcMotorCommand> motor_commands_;
  std::vector<double> servo_pulses_;
  std::vector<double> servo_angles_;  // positional servos' present output angle
  double wheelbase_m_ = 0;            // Ackermann: steered axle to driven axle
  std::vector<dGeomID> geoms_;        // hull, casters, tyres
  bool frozen_ = false;
};

}  // namespace sear
