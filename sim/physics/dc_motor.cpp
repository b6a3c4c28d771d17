#include "physics/dc_motor.hpp"

#include <algorithm>

namespace sear {

double dc_motor_torque(const MotorDesc& motor, const DcMotorCommand& command, double omega_radps) {
  // The slope of the torque-speed line is k_t k_e / R, the same at any voltage, so the supply
  // may differ from the datasheet's rating.
  const double back_emf_slope = motor.stall_torque_nm / motor.no_load_speed_radps;  // N*m per rad/s
  const double stall = motor.stall_torque_at_supply_nm();
  const double duty = std::clamp(command.duty, 0.0, 1.0);
  switch (command.direction) {
    case MotorDirection::Forward: return stall * duty - back_emf_slope * omega_radps;
    case MotorDirection::Reverse: return -stall * duty - back_emf_slope * omega_radps;
    case MotorDirection::Brake: return -back_emf_slope * omega_radps;
    case MotorDirection::Coast: return 0.0;
  }
  return 0.0;
}

double dc_motor_steady_speed(const MotorDesc& motor, double duty, double load_torque_nm) {
  const double drive = motor.stall_torque_at_supply_nm() * duty - load_torque_nm;
  if (drive <= 0) return 0.0;
  return drive / motor.stall_torque_nm * motor.no_load_speed_radps;
}

}  // namespace sear
