// Hobby servos commanded by pulse width: positional ones turn to an angle at their rated slew
// rate, continuous-rotation ones turn at a speed proportional to the pulse's offset from centre.
#pragma once

#include "scene/description.hpp"

namespace sear {

// Centre of the pulse range: neutral angle, or standstill for a continuous servo.
inline double servo_center_pulse_us(const ServoDesc& s) { return 0.5 * (s.min_pulse_us + s.max_pulse_us); }

// Positional: target angle (rad, positive = counter-clockwise seen from above, i.e. steer left).
double servo_target_angle(const ServoDesc& servo, double pulse_us);

// Continuous: target speed (rad/s) of the output shaft.
double servo_target_speed(const ServoDesc& servo, double pulse_us);

// A positional servo's output moves towards its target no faster than its rated speed.
double servo_slew(const ServoDesc& servo, double current_rad, double target_rad, double dt_s);

}  // namespace sear
