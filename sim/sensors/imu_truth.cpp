// Specific force and rate at an IMU's mount point, from an ODE body's state across steps.
#include "sensors/imu_truth.hpp"

#include <Eigen/Geometry>

namespace sear {

namespace {

Eigen::Matrix3d body_rotation(dBodyID body) {
  const dReal* r = dBodyGetRotation(body);  // 3x4, row-major
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = r[4 * i + j];
  return m;
}

Eigen::Vector3d vec(const dReal* v) { return {v[0], v[1], v[2]}; }

}  // namespace

ImuSample imu_from_kinematics(const Eigen::Matrix3d& world_from_body, const Eigen::Vector3d& accel_com_mps2,
                              const Eigen::Vector3d& omega_world_radps, const Eigen::Vector3d& alpha_world_radps2,
                              const ImuMount& mount, const Eigen::Vector3d& gravity_mps2) {
  const Eigen::Vector3d r = world_from_body * mount.position_m;
  const Eigen::Vector3d a_point =
      accel_com_mps2 + alpha_world_radps2.cross(r) + omega_world_radps.cross(omega_world_radps.cross(r));
  const Eigen::Matrix3d world_from_sensor = world_from_body * mount.body_from_sensor;
  ImuSample s;
  s.specific_force_mps2 = world_from_sensor.transpose() * (a_point - gravity_mps2);
  s.rate_radps = world_from_sensor.transpose() * omega_world_radps;
  return s;
}

ImuTruth::ImuTruth(const ImuMount& mount, const Eigen::Vector3d& gravity_mps2) : mount_(mount), gravity_(gravity_mps2) {}

ImuSample ImuTruth::update(dBodyID body, double step_s) {
  const Eigen::Vector3d v = vec(dBodyGetLinearVel(body));
  const Eigen::Vector3d w = vec(dBodyGetAngularVel(body));
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), alpha = Eigen::Vector3d::Zero();
  if (have_previous_ && step_s > 0) {
    a = (v - previous_velocity_) / step_s;
    alpha = (w - previous_omega_) / step_s;
  }
  previous_velocity_ = v;
  previous_omega_ = w;
  have_previous_ = true;
  return imu_from_kinematics(body_rotation(body), a, w, alpha, mount_, gravity_);
}

Eigen::Matrix3d ImuTruth::world_from_sensor(dBodyID body) const { return body_rotation(body) * mount_.body_from_sensor; }

}  // namespace sear
