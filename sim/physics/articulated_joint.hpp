// A URDF link on a joint that moves and is no wheel: its own ODE body on a hinge or slider to
// its parent body, with the URDF's stops, viscous damping and Coulomb friction, and, when a
// servo turns it, the servo's position loop on the joint's motor.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "physics/physics_world.hpp"
#include "scene/description.hpp"

namespace sear {

// A collision shape fixed to `body`, placed in its frame; tagged by the caller.
dGeomID attach_shape(PhysicsWorld& physics, const ShapeDesc& shape, dBodyID body);

// How far below its origin the shape reaches when its frame is turned by `rotation` (z up).
double depth_below(const ShapeDesc& shape, const Eigen::Matrix3d& rotation);

// A motor row holding `body`'s rate relative to `other` at zero, about `axis` (`turning`) or along
// it, with at most `max_effort`: a brake or Coulomb friction. A `cfm` above 0 makes it viscous,
// damping 1 / cfm, which ODE solves implicitly at the end of the step, so it cannot diverge.
void zero_rate_row(dWorldID world, dBodyID body, dBodyID other, const Eigen::Vector3d& axis, bool turning,
                   double max_effort, double cfm);

class ArticulatedJoint {
 public:
  // Builds the link at rest (every joint at zero) for a robot whose chassis frame starts at
  // `robot_pose` in the world, hung on `parent` (the chassis or another such link).
  ArticulatedJoint(PhysicsWorld& physics, const JointLinkDesc& desc, dBodyID parent, const Eigen::Isometry3d& robot_pose,
                   int entity);

  dBodyID body() const { return body_; }
  const std::vector<dGeomID>& geoms() const { return geoms_; }
  // From the URDF's zero, positive about (along) its axis: rad or m, rad/s or m/s.
  double position() const;
  double rate() const;

  // The joint's own motor: towards `rate` with at most `max_effort` (N*m or N); 0 lets go.
  void drive(double rate, double max_effort);
  // A servo on the joint: positional ones slew `output_rad` (their output shaft) towards the
  // pulse's angle, kept within the joint's stops, and the joint follows it; continuous ones
  // turn it at the pulse's speed. pulse_us 0: no pulses, the servo lets go.
  void follow_servo(const ServoDesc& servo, double pulse_us, double& output_rad, double dt_s);

 private:
  bool hinge_, limited_;
  double lower_, upper_, velocity_;  // what the servo loop needs of the JointLinkDesc
  dBodyID body_;
  dJointID joint_;
  std::vector<dGeomID> geoms_;
};

}  // namespace sear
