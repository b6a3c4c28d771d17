#include "physics/vehicle.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "physics/ackermann.hpp"
#include "physics/servo.hpp"

namespace sear {
namespace {

constexpr double kSpawnClearance_m = 0.002;  // dropped from just above the ground so it settles at once
constexpr double kSteerGain_per_s = 20.0;    // steering joint's position loop, fast against servo slew rates
// Hinge-2 suspension of steered wheels, as spring and damper: stiff enough to feel rigid.
constexpr double kSuspensionStiffness_Npm = 20000.0;
constexpr double kSuspensionDamping_Nspm = 200.0;

Eigen::Vector3d to_eigen(const dReal* v) { return {v[0], v[1], v[2]}; }

Eigen::Matrix3d rotation_of(dBodyID body) {
  const dReal* r = dBodyGetRotation(body);  // 3x4, row-major
  Eigen::Matrix3d m;
  m << r[0], r[1], r[2], r[4], r[5], r[6], r[8], r[9], r[10];
  return m;
}

void set_rotation(dBodyID body, const Eigen::Matrix3d& m) {
  dMatrix3 r = {m(0, 0), m(0, 1), m(0, 2), 0, m(1, 0), m(1, 1), m(1, 2), 0, m(2, 0), m(2, 1), m(2, 2), 0};
  dBodySetRotation(body, r);
}

}  // namespace

Vehicle::Vehicle(PhysicsWorld& physics, const RobotDesc& desc)
    : desc_(desc),
      entity_(physics.add_entity(desc.name)),
      motor_commands_(desc.motors.size()),
      servo_pulses_(desc.servos.size()),
      servo_angles_(desc.servos.size(), 0.0) {
  for (std::size_t i = 0; i < desc.servos.size(); ++i) servo_pulses_[i] = servo_center_pulse_us(desc.servos[i]);

  // It starts level, just clear of the terrain under each wheel, caster and the chassis centre.
  const Eigen::Vector2d xy = desc.start_xy_m;
  const Eigen::Matrix2d yaw2 = Eigen::Rotation2Dd(desc.start_yaw_rad).toRotationMatrix();
  const auto ground = [&](const Eigen::Vector2d& at) {
    const double h = physics.terrain_height(at.x(), at.y(), std::nan(""));
    if (std::isnan(h))
      throw PlacementError(fmt::format("{}:{}: error: robot '{}' starts at ({:.2f}, {:.2f}) m, where there is no terrain",
                                           desc.source.file, desc.source.line, desc.name, at.x(), at.y()));
    return h;
  };
  double origin_z = ground(xy) - desc.chassis.bottom_z_m;
  const auto clear = [&](const Eigen::Vector3d& p, double radius) {
    origin_z = std::max(origin_z, ground(xy + yaw2 * p.head<2>()) - (p.z() - radius));
  };
  for (const auto& w : desc.wheels) clear(w.position_m, w.radius_m);
  for (const auto& c : desc.casters) clear(c.position_m, c.radius_m);
  // A live link hanging below the chassis (at rest) starts clear of the ground too.
  for (const auto& j : desc.joints)
    for (const auto& part : j.parts) clear(j.position_m + j.rotation * part.position_m, depth_below(part, j.rotation));
  const Eigen::Vector3d origin(xy.x(), xy.y(), origin_z + kSpawnClearance_m);
  const Eigen::Matrix3d yaw = Eigen::AngleAxisd(desc.start_yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();

  chassis_ = dBodyCreate(physics.world());
  dMass mass;
  if (desc.chassis.given_inertia) {
    // A URDF's lumped links: the chassis origin is their centre of mass, as ODE needs it.
    const Eigen::Matrix3d& I = desc.chassis.inertia_kgm2;
    dMassSetParameters(&mass, desc.chassis.mass_kg, 0, 0, 0, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
  } else {
    // A mesh chassis takes the inertia of its bounding box: a mesh need not be closed (ODE's mesh
    // inertia needs a closed one), and for the compact chassis of small robots the box is close.
    dMassSetBoxTotal(&mass, desc.chassis.mass_kg, desc.chassis.size_m.x(), desc.chassis.size_m.y(),
                     desc.chassis.size_m.z());
  }
  dBodySetMass(chassis_, &mass);
  dBodySetPosition(chassis_, origin.x(), origin.y(), origin.z());
  set_rotation(chassis_, yaw);
  const int chassis_material = physics.material_index(desc.chassis.material);
  if (desc.chassis.shape == ChassisDesc::Shape::Parts) {
    for (const auto& part : desc.chassis.parts) add_part(physics, part, chassis_material);
  } else {
    dGeomID hull = desc.chassis.shape == ChassisDesc::Shape::Box
                       ? dCreateBox(physics.dynamic_space(), desc.chassis.size_m.x(), desc.chassis.size_m.y(),
                                    desc.chassis.size_m.z())
                       : dCreateTriMesh(physics.dynamic_space(), physics.add_mesh_data(desc.chassis.mesh), nullptr,
                                        nullptr, nullptr);
    dGeomSetBody(hull, chassis_);
    geoms_.push_back(hull);
    physics.tag(hull, GeomRole::Chassis, entity_, chassis_material);
  }

  for (const auto& c : desc.casters) {
    dGeomID ball = dCreateSphere(physics.dynamic_space(), c.radius_m);
    dGeomSetBody(ball, chassis_);
    geoms_.push_back(ball);
    dGeomSetOffsetPosition(ball, c.position_m.x(), c.position_m.y(), c.position_m.z());
    physics.tag(ball, GeomRole::Caster, entity_, chassis_material);
  }

  // ODE cylinders run along their local Z; -90 degrees about X lays that along the robot's +Y (left).
  const Eigen::Matrix3d wheel_rotation = yaw * Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector3d up = yaw * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d left = yaw * Eigen::Vector3d::UnitY();
  double fastest_motor = 10.0;
  for (const auto& m : desc.motors) fastest_motor = std::max(fastest_motor, m.no_load_speed_at_supply_radps());
  for (const auto& s : desc.servos) fastest_motor = std::max(fastest_motor, s.speed_radps);

  for (const auto& w : desc.wheels) {
    Wheel wheel{};
    wheel.steered = w.steered;
    wheel.body = dBodyCreate(physics.world());
    dMass wm;
    if (w.given_inertia) {
      const Eigen::Matrix3d& I = w.inertia_kgm2;
      dMassSetParameters(&wm, w.mass_kg, 0, 0, 0, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
    } else {
      dMassSetCylinderTotal(&wm, w.mass_kg, 3, w.radius_m, w.width_m);
    }
    dBodySetMass(wheel.body, &wm);
    const Eigen::Vector3d centre = origin + yaw * w.position_m;
    dBodySetPosition(wheel.body, centre.x(), centre.y(), centre.z());
    set_rotation(wheel.body, wheel_rotation);
    // A fast wheel spins many radians per step: integrate its spin exactly about the axle.
    dBodySetFiniteRotationMode(wheel.body, 1);
    dBodySetMaxAngularSpeed(wheel.body, 10.0 * fastest_motor);
    dGeomID tyre = dCreateCylinder(physics.dynamic_space(), w.radius_m, w.width_m);
    dGeomSetBody(tyre, wheel.body);
    geoms_.push_back(tyre);
    physics.tag(tyre, GeomRole::Wheel, entity_, physics.material_index(w.material));
    dGeomID tread = dCreateSphere(physics.dynamic_space(), w.radius_m);
    dGeomSetBody(tread, wheel.body);
    geoms_.push_back(tread);
    physics.tag(tread, GeomRole::Tread, entity_, physics.material_index(w.material));

    if (w.steered) {
      wheel.joint = dJointCreateHinge2(physics.world(), nullptr);
      dJointAttach(wheel.joint, chassis_, wheel.body);
      dJointSetHinge2Anchor(wheel.joint, centre.x(), centre.y(), centre.z());
      const dReal axis1[3] = {up.x(), up.y(), up.z()};
      const dReal axis2[3] = {left.x(), left.y(), left.z()};
      dJointSetHinge2Axes(wheel.joint, axis1, axis2);
      const double h = physics.step_s();
      const double denominator = h * kSuspensionStiffness_Npm + kSuspensionDamping_Nspm;
      dJointSetHinge2Param(wheel.joint, dParamSuspensionERP, h * kSuspensionStiffness_Npm / denominator);
      dJointSetHinge2Param(wheel.joint, dParamSuspensionCFM, 1.0 / denominator);
    } else {
      wheel.joint = dJointCreateHinge(physics.world(), nullptr);
      dJointAttach(wheel.joint, wheel.body, chassis_);
      dJointSetHingeAnchor(wheel.joint, centre.x(), centre.y(), centre.z());
      dJointSetHingeAxis(wheel.joint, left.x(), left.y(), left.z());
    }
    wheels_.push_back(wheel);
  }

  // A URDF's live joints, parents first, each link hung on its parent's body.
  Eigen::Isometry3d robot_pose = Eigen::Isometry3d::Identity();
  robot_pose.translation() = origin;
  robot_pose.linear() = yaw;
  for (const auto& j : desc.joints)
    joints_.emplace_back(physics, j, j.parent < 0 ? chassis_ : joints_[static_cast<std::size_t>(j.parent)].body(),
                         robot_pose, entity_);
  for (const auto& j : joints_) geoms_.insert(geoms_.end(), j.geoms().begin(), j.geoms().end());

  for (const auto& m : desc.motors) {
    motor_wheels_.emplace_back();
    for (const auto& name : m.wheels) motor_wheels_.back().push_back(wheel_index(name));
  }
  for (const auto& s : desc.servos) {
    servo_wheels_.emplace_back();
    for (const auto& name : s.wheels) servo_wheels_.back().push_back(wheel_index(name));
    servo_joint_.push_back(-1);
    for (std::size_t j = 0; j < desc.joints.size(); ++j)
      if (!s.joint.empty() && desc.joints[j].joint == s.joint) servo_joint_.back() = static_cast<int>(j);
  }

  // Each motor acts on its wheels through their joints' motor rows, as a velocity target with a
  // constraint force mixing of n / k: ODE then solves the row for the torque k / n * (target -
  // omega) at the speed omega the wheel has at the end of the step, together with the contacts,
  // so no ratio of damping to inertia or step size can make it diverge. Gearbox friction, a
  // separate Coulomb limit, takes a second row: an angular motor held at zero speed with its
  // force capped at each wheel's share of the friction.
  for (std::size_t m = 0; m < desc.motors.size(); ++m) {
    const MotorDesc& motor = desc.motors[m];
    const double n = static_cast<double>(motor_wheels_[m].size());
    const double cfm = n / dc_motor_drive(motor, {}).damping_nmps;
    const double share = motor.gear_friction_nm / n;
    for (std::size_t w : motor_wheels_[m]) {
      Wheel& wheel = wheels_[w];
      if (wheel.steered) dJointSetHinge2Param(wheel.joint, dParamCFM2, cfm);
      else dJointSetHingeParam(wheel.joint, dParamCFM, cfm);
      set_drive(wheel, 0.0, 0.0);
      if (share <= 0) continue;
      wheel.friction = dJointCreateAMotor(physics.world(), nullptr);
      dJointAttach(wheel.friction, wheel.body, chassis_);
      dJointSetAMotorMode(wheel.friction, dAMotorUser);
      dJointSetAMotorNumAxes(wheel.friction, 1);
      dJointSetAMotorAxis(wheel.friction, 0, 1, left.x(), left.y(), left.z());  // rel 1: turns with the wheel
      dJointSetAMotorParam(wheel.friction, dParamVel, 0);
      dJointSetAMotorParam(wheel.friction, dParamFMax, share);
    }
  }

  // A URDF wheel joint's own friction (Coulomb) and damping (viscous).
  for (std::size_t i = 0; i < desc.wheels.size(); ++i) {
    const WheelDesc& w = desc.wheels[i];
    if (w.joint_friction_nm > 0)
      zero_rate_row(physics.world(), wheels_[i].body, chassis_, left, true, w.joint_friction_nm, 0);
    if (w.joint_damping_nmps > 0)
      zero_rate_row(physics.world(), wheels_[i].body, chassis_, left, true, dInfinity, 1.0 / w.joint_damping_nmps);
  }

  if (desc.drive == DriveKind::Ackermann) {
    double steered_x = 0, driven_x = 0;
    for (const auto& w : desc.wheels) (w.steered ? steered_x : driven_x) += 0.5 * w.position_m.x();
    wheelbase_m_ = std::abs(steered_x - driven_x);
  }
}

void Vehicle::add_part(PhysicsWorld& physics, const ShapeDesc& part, int material) {
  dGeomID g = attach_shape(physics, part, chassis_);
  geoms_.push_back(g);
  physics.tag(g, GeomRole::Chassis, entity_, material);
}

std::size_t Vehicle::wheel_index(const std::string& name) const {
  for (std::size_t i = 0; i < desc_.wheels.size(); ++i)
    if (desc_.wheels[i].name == name) return i;
  throw std::logic_error("robot '" + desc_.name + "': wheel '" + name + "' was not validated by the loader");
}

int Vehicle::motor_index(const std::string& name) const {
  for (std::size_t i = 0; i < desc_.motors.size(); ++i)
    if (desc_.motors[i].name == name) return static_cast<int>(i);
  return -1;
}

int Vehicle::servo_index(const std::string& name) const {
  for (std::size_t i = 0; i < desc_.servos.size(); ++i)
    if (desc_.servos[i].name == name) return static_cast<int>(i);
  return -1;
}

Eigen::Vector3d Vehicle::axle_world(std::size_t wheel) const {
  return rotation_of(wheels_[wheel].body).col(2);
}

double Vehicle::wheel_speed(std::size_t wheel) const {
  const Eigen::Vector3d relative =
      to_eigen(dBodyGetAngularVel(wheels_[wheel].body)) - to_eigen(dBodyGetAngularVel(chassis_));
  return relative.dot(axle_world(wheel));
}

void Vehicle::set_drive(const Wheel& wheel, double target_radps, double max_torque_nm) {
  if (wheel.steered) {
    // Hinge-2 rows measure the chassis (body 1) relative to the wheel: the wheel's speed is minus that.
    dJointSetHinge2Param(wheel.joint, dParamVel2, -target_radps);
    dJointSetHinge2Param(wheel.joint, dParamFMax2, max_torque_nm);
  } else {
    dJointSetHingeParam(wheel.joint, dParamVel, target_radps);
    dJointSetHingeParam(wheel.joint, dParamFMax, max_torque_nm);
  }
}

void Vehicle::freeze() {
  if (frozen_) return;
  frozen_ = true;
  for (auto& c : motor_commands_) c = DcMotorCommand{};
  for (auto& p : servo_pulses_) p = 0;
  std::vector<dBodyID> bodies{chassis_};
  for (const auto& w : wheels_) bodies.push_back(w.body);
  for (const auto& j : joints_) bodies.push_back(j.body());
  for (dBodyID b : bodies) {
    dBodySetLinearVel(b, 0, 0, 0);
    dBodySetAngularVel(b, 0, 0, 0);
    dBodySetForce(b, 0, 0, 0);
    dBodySetTorque(b, 0, 0, 0);
    // Disabled bodies with no contacts stay put: ODE only wakes a body that a joint ties to an awake one.
    dBodyDisable(b);
  }
  for (dGeomID g : geoms_) dGeomDisable(g);
}

void Vehicle::apply_actuators(double dt_s) {
  if (frozen_) return;
  for (std::size_t i = 0; i < wheels_.size(); ++i) {
    const Eigen::Vector3d axle = axle_world(i);
    dBodySetFiniteRotationAxis(wheels_[i].body, axle.x(), axle.y(), axle.z());
  }

  // A motor driving several wheels acts through an open differential: it turns at their mean
  // speed and splits its torque evenly. The joint rows give each wheel k / n * (target -
  // omega_i); the differential's part, k / n * (omega_i - mean), moves torque between the wheels
  // and sums to nothing, so it is added explicitly. Against the implicit damping of the same
  // size it cannot grow: it only lends the wheels' speed difference an inertia of k h / n.
  for (std::size_t m = 0; m < desc_.motors.size(); ++m) {
    const auto& driven = motor_wheels_[m];
    const DcMotorDrive d = dc_motor_drive(desc_.motors[m], motor_commands_[m]);
    for (std::size_t w : driven) set_drive(wheels_[w], d.target_radps, d.engaged ? dInfinity : 0.0);
    if (!d.engaged || driven.size() < 2) continue;
    const double n = static_cast<double>(driven.size());
    double mean = 0;
    for (std::size_t w : driven) mean += wheel_speed(w);
    mean /= n;
    for (std::size_t w : driven) {
      const Eigen::Vector3d torque = d.damping_nmps / n * (wheel_speed(w) - mean) * axle_world(w);
      dBodyAddTorque(wheels_[w].body, torque.x(), torque.y(), torque.z());
      dBodyAddTorque(chassis_, -torque.x(), -torque.y(), -torque.z());
    }
  }

  for (std::size_t s = 0; s < desc_.servos.size(); ++s) {
    const ServoDesc& servo = desc_.servos[s];
    if (servo_joint_[s] >= 0) {
      joints_[static_cast<std::size_t>(servo_joint_[s])].follow_servo(servo, servo_pulses_[s], servo_angles_[s], dt_s);
      continue;
    }
    if (servo_pulses_[s] <= 0) {
      // Without pulses a hobby servo's driver is off: its output turns freely.
      for (std::size_t w : servo_wheels_[s]) {
        if (servo.kind == ServoDesc::Kind::Continuous) dJointSetHingeParam(wheels_[w].joint, dParamFMax, 0);
        else dJointSetHinge2Param(wheels_[w].joint, dParamFMax, 0);
      }
      continue;
    }
    if (servo.kind == ServoDesc::Kind::Continuous) {
      const double speed = servo_target_speed(servo, servo_pulses_[s]);
      for (std::size_t w : servo_wheels_[s]) {
        dJointSetHingeParam(wheels_[w].joint, dParamVel, speed);
        dJointSetHingeParam(wheels_[w].joint, dParamFMax, servo.torque_nm);
      }
      continue;
    }
    servo_angles_[s] = servo_slew(servo, servo_angles_[s], servo_target_angle(servo, servo_pulses_[s]), dt_s);
    for (std::size_t w : servo_wheels_[s]) {
      const double target = ackermann_wheel_angle(servo_angles_[s], wheelbase_m_, desc_.wheels[w].position_m.y());
      // ODE measures the hinge-2 angle and its motor speed as the chassis (body 1) relative to the
      // wheel: the wheel's own steer to the left is the negative of both.
      const double steer = -dJointGetHinge2Angle1(wheels_[w].joint);
      const double limit = 2.0 * servo.speed_radps;
      const double rate = std::clamp(kSteerGain_per_s * (target - steer), -limit, limit);
      dJointSetHinge2Param(wheels_[w].joint, dParamVel, -rate);
      dJointSetHinge2Param(wheels_[w].joint, dParamFMax, servo.torque_nm);
    }
  }
}

VehicleState Vehicle::state() const {
  VehicleState s;
  s.position_m = to_eigen(dBodyGetPosition(chassis_));
  const Eigen::Matrix3d r = rotation_of(chassis_);
  s.roll_pitch_yaw = {std::atan2(r(2, 1), r(2, 2)), -std::asin(std::clamp(r(2, 0), -1.0, 1.0)),
                      std::atan2(r(1, 0), r(0, 0))};
  s.velocity_mps = to_eigen(dBodyGetLinearVel(chassis_));
  s.angular_velocity = to_eigen(dBodyGetAngularVel(chassis_));
  s.forward_speed_mps = s.velocity_mps.dot(r.col(0));
  return s;
}

}  // namespace sear
