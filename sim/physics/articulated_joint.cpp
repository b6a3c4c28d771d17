// A live URDF joint in ODE: the link's body, its hinge or slider with stops, the rows that give
// it damping and friction, and a servo's position loop.
#include "physics/articulated_joint.hpp"

#include <algorithm>
#include <cmath>

#include "physics/servo.hpp"

namespace sear {
namespace {

// The joint's position loop behind a positional servo, as for steering (vehicle.cpp): fast
// against hobby servos' slew rates, so the joint trails the servo's output by speed / gain.
constexpr double kServoGain_per_s = 20.0;

void set_ode_rotation(const Eigen::Matrix3d& m, dMatrix3 r) {
  const dReal rows[12] = {m(0, 0), m(0, 1), m(0, 2), 0, m(1, 0), m(1, 1), m(1, 2), 0, m(2, 0), m(2, 1), m(2, 2), 0};
  std::copy(rows, rows + 12, r);
}

}  // namespace

dGeomID attach_shape(PhysicsWorld& physics, const ShapeDesc& part, dBodyID body) {
  dGeomID g = nullptr;
  switch (part.kind) {
    case ShapeDesc::Kind::Box:
      g = dCreateBox(physics.dynamic_space(), part.size_m.x(), part.size_m.y(), part.size_m.z());
      break;
    case ShapeDesc::Kind::Cylinder:
      g = dCreateCylinder(physics.dynamic_space(), part.size_m.x(), part.size_m.z());
      break;
    case ShapeDesc::Kind::Sphere:
      g = dCreateSphere(physics.dynamic_space(), part.size_m.x());
      break;
    case ShapeDesc::Kind::Mesh:
      g = dCreateTriMesh(physics.dynamic_space(), physics.add_mesh_data(part.mesh), nullptr, nullptr, nullptr);
      break;
  }
  dGeomSetBody(g, body);
  dGeomSetOffsetPosition(g, part.position_m.x(), part.position_m.y(), part.position_m.z());
  dMatrix3 r;
  set_ode_rotation(part.rotation, r);
  dGeomSetOffsetRotation(g, r);
  return g;
}

double depth_below(const ShapeDesc& s, const Eigen::Matrix3d& rotation) {
  const Eigen::Vector3d down = (rotation * s.rotation).row(2);  // world z in the shape's axes
  switch (s.kind) {
    case ShapeDesc::Kind::Box:
      return 0.5 * s.size_m.cwiseProduct(down.cwiseAbs()).sum();
    case ShapeDesc::Kind::Cylinder:
      return std::abs(down.z()) * 0.5 * s.size_m.z() + s.size_m.x() * std::sqrt(std::max(0.0, 1 - down.z() * down.z()));
    case ShapeDesc::Kind::Sphere:
      return s.size_m.x();
    case ShapeDesc::Kind::Mesh:
      break;
  }
  double depth = 0;
  for (const auto& v : s.mesh.vertices) depth = std::max(depth, -down.dot(v.cast<double>()));
  return depth;
}

ArticulatedJoint::ArticulatedJoint(PhysicsWorld& physics, const JointLinkDesc& desc, dBodyID parent,
                                   const Eigen::Isometry3d& robot_pose, int entity)
    : hinge_(desc.kind == JointLinkDesc::Kind::Hinge),
      limited_(desc.limited),
      lower_(desc.lower),
      upper_(desc.upper),
      velocity_(desc.velocity) {
  const dWorldID world = physics.world();
  body_ = dBodyCreate(world);
  dMass mass;
  const Eigen::Matrix3d& I = desc.inertia_kgm2;
  dMassSetParameters(&mass, desc.mass_kg, 0, 0, 0, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
  dBodySetMass(body_, &mass);
  const Eigen::Vector3d at = robot_pose * desc.position_m;
  dBodySetPosition(body_, at.x(), at.y(), at.z());
  dMatrix3 r;
  set_ode_rotation(robot_pose.linear() * desc.rotation, r);
  dBodySetRotation(body_, r);
  const int material = physics.material_index(desc.material);
  for (const auto& part : desc.parts) {
    geoms_.push_back(attach_shape(physics, part, body_));
    physics.tag(geoms_.back(), GeomRole::Chassis, entity, material);
  }

  // Both bodies stand at rest where the URDF's zero puts them, so ODE's angle and position
  // count from it. Body 1 is the child: positive turns it about the axis, as URDF has it.
  const Eigen::Vector3d anchor = robot_pose * desc.anchor_m;
  const Eigen::Vector3d axis = robot_pose.linear() * desc.axis;
  const bool hinge = hinge_;
  joint_ = hinge ? dJointCreateHinge(world, nullptr) : dJointCreateSlider(world, nullptr);
  dJointAttach(joint_, body_, parent);
  if (hinge) {
    dJointSetHingeAnchor(joint_, anchor.x(), anchor.y(), anchor.z());
    dJointSetHingeAxis(joint_, axis.x(), axis.y(), axis.z());
  } else {
    dJointSetSliderAxis(joint_, axis.x(), axis.y(), axis.z());
  }
  const auto set = [&](dJointID j, int parameter, double value) {
    if (hinge) dJointSetHingeParam(j, parameter, value);
    else dJointSetSliderParam(j, parameter, value);
  };
  // The stops: ODE holds them as constraints with the world's ERP and CFM, which let a stop
  // give by torque * step * CFM / ERP (5e-9 rad per N*m at 1 ms) and correct an overshoot of
  // at most one step's travel by ERP a step.
  if (desc.limited) {
    set(joint_, dParamLoStop, std::isfinite(desc.lower) ? desc.lower : -dInfinity);
    set(joint_, dParamHiStop, std::isfinite(desc.upper) ? desc.upper : dInfinity);
  }
  drive(0, 0);

  // Damping and friction, each a motor row held at zero relative speed about (along) the
  // axis: friction caps its torque at the Coulomb value; damping leaves it uncapped with a
  // constraint force mixing of 1 / c, so ODE solves torque = -c * rate at the end of the
  // step (implicitly: no damping can make it diverge). Rows of their own, so that a servo
  // on the joint's own motor still meets both.
  if (desc.friction > 0) zero_rate_row(world, body_, parent, axis, hinge, desc.friction, 0);
  if (desc.damping > 0) zero_rate_row(world, body_, parent, axis, hinge, dInfinity, 1.0 / desc.damping);
}

void zero_rate_row(dWorldID world, dBodyID body, dBodyID other, const Eigen::Vector3d& axis, bool turning,
                   double max_effort, double cfm) {
  if (turning) {
    dJointID j = dJointCreateAMotor(world, nullptr);
    dJointAttach(j, body, other);
    dJointSetAMotorMode(j, dAMotorUser);
    dJointSetAMotorNumAxes(j, 1);
    dJointSetAMotorAxis(j, 0, 1, axis.x(), axis.y(), axis.z());
    dJointSetAMotorParam(j, dParamVel, 0);
    dJointSetAMotorParam(j, dParamFMax, max_effort);
    if (cfm > 0) dJointSetAMotorParam(j, dParamCFM, cfm);
  } else {
    dJointID j = dJointCreateLMotor(world, nullptr);
    dJointAttach(j, body, other);
    dJointSetLMotorNumAxes(j, 1);
    dJointSetLMotorAxis(j, 0, 1, axis.x(), axis.y(), axis.z());
    dJointSetLMotorParam(j, dParamVel, 0);
    dJointSetLMotorParam(j, dParamFMax, max_effort);
    if (cfm > 0) dJointSetLMotorParam(j, dParamCFM, cfm);
  }
}

double ArticulatedJoint::position() const {
  return hinge_ ? dJointGetHingeAngle(joint_) : dJointGetSliderPosition(joint_);
}

double ArticulatedJoint::rate() const {
  return hinge_ ? dJointGetHingeAngleRate(joint_)
                                                   : dJointGetSliderPositionRate(joint_);
}

void ArticulatedJoint::drive(double rate, double max_effort) {
  if (hinge_) {
    dJointSetHingeParam(joint_, dParamVel, rate);
    dJointSetHingeParam(joint_, dParamFMax, max_effort);
  } else {
    dJointSetSliderParam(joint_, dParamVel, rate);
    dJointSetSliderParam(joint_, dParamFMax, max_effort);
  }
}

void ArticulatedJoint::follow_servo(const ServoDesc& servo, double pulse_us, double& output_rad, double dt_s) {
  if (pulse_us <= 0) {  // without pulses a hobby servo's driver is off: the joint turns freely
    drive(0, 0);
    return;
  }
  if (servo.kind == ServoDesc::Kind::Continuous) {
    drive(servo_target_speed(servo, pulse_us), servo.torque_nm);
    return;
  }
  double target = servo_target_angle(servo, pulse_us);
  if (limited_) target = std::clamp(target, lower_, upper_);
  output_rad = servo_slew(servo, output_rad, target, dt_s);
  double limit = 2.0 * servo.speed_radps;  // catches up a lag, within the URDF's velocity
  if (velocity_ > 0) limit = std::min(limit, velocity_);
  drive(std::clamp(kServoGain_per_s * (output_rad - position()), -limit, limit), servo.torque_nm);
}

}  // namespace sear
