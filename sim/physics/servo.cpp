#include "physics/servo.hpp"

#include <algorithm>

namespace sear {

namespace {
double pulse_fraction(const ServoDesc& s, double pulse_us) {
  const double half_span = 0.5 * (s.max_pulse_us - s.min_pulse_us);
  return std::clamp((pulse_us - servo_center_pulse_us(s)) / half_span, -1.0, 1.0);
}
}  // namespace

double servo_target_angle(const ServoDesc& servo, double pulse_us) {
  return pulse_fraction(servo, pulse_us) * 0.5 * servo.range_rad;
}

double servo_target_speed(const ServoDesc& servo, double pulse_us) {
  return pulse_fraction(servo, pulse_us) * servo.speed_radps;
}

double servo_slew(const ServoDesc& servo, double current_rad, double target_rad, double dt_s) {
  const double max_step = servo.speed_radps * dt_s;
  return current_rad + std::clamp(target_rad - current_rad, -max_step, max_step);
}

}  // namespace sear
