// What an IMU mounted on a moving body physically senses: specific force (acceleration minus
// gravity, so a sensor at rest reads +1 g up) and angular rate, both along the sensor's own axes,
// including the lever-arm terms of a sensor mounted away from the body's centre of mass.
// Frames: world x east, y north, z up; body (robot) x forward, y left, z up.
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>

namespace sear {

// Where the sensor sits on the body: its position from the body's origin (ODE's body origin is
// its centre of mass) and its axes, as the columns of body_from_sensor.
struct ImuMount {
  Eigen::Vector3d position_m{0, 0, 0};
  Eigen::Matrix3d body_from_sensor = Eigen::Matrix3d::Identity();
};

struct ImuSample {
  Eigen::Vector3d specific_force_mps2{0, 0, 0};
  Eigen::Vector3d rate_radps{0, 0, 0};
};

// The rigid-body kinematics of a point r on a body: a_p = a + alpha x r + w x (w x r), all in the
// world frame; f = a_p - g, then turned into sensor axes. Pure, for tests and for any body.
ImuSample imu_from_kinematics(const Eigen::Matrix3d& world_from_body, const Eigen::Vector3d& accel_com_mps2,
                              const Eigen::Vector3d& omega_world_radps, const Eigen::Vector3d& alpha_world_radps2,
                              const ImuMount& mount, const Eigen::Vector3d& gravity_mps2);

// Tracks one body across physics steps. The body's linear and angular accelerations are the
// change of its velocities over the step just taken divided by the step: with ODE's
// semi-implicit Euler (v_{k+1} = v_k + h F/m) that is exactly the acceleration the step applied,
// contact and joint impulses included, so a body held still by contacts reads a = 0 and a free
// body reads a = g. The first update after construction or reset() has no previous velocity and
// takes both accelerations as zero.
class ImuTruth {
 public:
  ImuTruth(const ImuMount& mount, const Eigen::Vector3d& gravity_mps2);

  // Call once after every physics step, with the step's length.
  ImuSample update(dBodyID body, double step_s);
  void reset() { have_previous_ = false; }

  // The sensor's axes in the world (columns), for turning world vectors such as the magnetic
  // field into the sensor frame.
  Eigen::Matrix3d world_from_sensor(dBodyID body) const;

 private:
  ImuMount mount_;
  Eigen::Vector3d gravity_;
  bool have_previous_ = false;
  Eigen::Vector3d previous_velocity_{0, 0, 0};
  Eigen::Vector3d previous_omega_{0, 0, 0};
};

}  // namespace sear
