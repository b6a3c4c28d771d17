// A sensor's axes on its robot from the mount angles of its row (yaw, then pitch, then roll), so
// that every kind with a Full mount turns the same way.
#pragma once

#include <Eigen/Geometry>

#include "scene/description.hpp"

namespace sear {

// Columns: the sensor's x, y, z axes in the robot frame. Pitch is positive nose down, as for the
// rangers' beams, which is a rotation about +y by +pitch.
inline Eigen::Matrix3d body_from_sensor(const DeviceDesc& d) {
  return (Eigen::AngleAxisd(d.yaw_rad, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(d.pitch_rad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(d.roll_rad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace sear
