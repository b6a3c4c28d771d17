#include "physics/ackermann.hpp"

#include <cmath>

namespace sear {

double ackermann_wheel_angle(double center_angle_rad, double wheelbase_m, double lateral_offset_m) {
  const double t = std::tan(center_angle_rad);
  return std::atan2(wheelbase_m * t, wheelbase_m - lateral_offset_m * t);
}

}  // namespace sear
