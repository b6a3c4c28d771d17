#include "physics/dc_motor.hpp"

#include <algorithm>

namespace sear {

DcMotorDrive dc_motor_drive(const MotorDesc& motor, const DcMotorCommand& command) {
  DcMotorDrive d;
  // The slope of the torque-speed line is k_t k_e / R, the same at any voltage, so the supply
  // may differ from the datasheet's rating: only the target speed scales with it.
  d.damping_nmps = motor.stall_torque_nm / motor.no_load_speed_radps;
  const double duty = std::clamp(command.duty, 0.0, 1.0);
  switch (command.direction) {
    case MotorDirection::Forward: d.engaged = true; d.target_radps = duty * motor.no_load_speed_at_supply_radps(); break;
    case MotorDirection::Reverse: d.engaged = true; d.target_radps = -duty * motor.no_load_speed_at_supply_radps(); break;
    case MotorDirection::Brake: d.engaged = true; d.target_radps = 0; break;
    case MotorDirection::Coast: d.engaged = false; break;
  }
  return d;
}

double dc_motor_torque(const MotorDesc& motor, const DcMotorCommand& command, double omega_radps) {
  const DcMotorDrive d = dc_motor_drive(motor, command);
  return d.engaged ? d.damping_nmps * (d.target_radps - omega_radps) : 0.0;
}

double dc_motor_steady_speed(const MotorDesc& motor, double duty, double load_torque_nm) {
  const double drive = motor.stall_torque_at_supply_nm() * duty - load_torque_nm;
  if (drive <= 0) return 0.0;
  return drive / motor.stall_torque_nm * motor.no_load_speed_radps;
}

}  // namespace sear
