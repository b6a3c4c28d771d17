// Ackermann steering geometry: each steered wheel turns about the same centre on the rear axle line.
#pragma once

namespace sear {

// Angle of a steered wheel `lateral_offset_m` left of the centre line, for a car whose virtual
// centre wheel is steered to `center_angle_rad` (positive = left) with wheelbase `wheelbase_m`.
// tan(wheel) = L tan(centre) / (L - y tan(centre)): the inner wheel turns more than the outer.
double ackermann_wheel_angle(double center_angle_rad, double wheelbase_m, double lateral_offset_m);

}  // namespace sear
