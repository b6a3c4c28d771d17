// A brushed DC gearmotor behind an H-bridge, as its datasheet describes it: stall torque and
// no-load speed at the supply voltage, a straight torque-speed line in between.
#pragma once

#include "scene/description.hpp"

namespace sear {

struct DcMotorCommand {
  double duty = 0;  // PWM duty 0..1
  MotorDirection direction = MotorDirection::Coast;
};

// Output-shaft torque in N*m for a command at shaft speed `omega_radps`. The PWM is averaged:
// sign-magnitude drive with slow decay applies duty * V on average, and the winding's electrical
// time constant (well under a millisecond for small motors) is neglected against the 1 ms step.
// Brake shorts the winding (V = 0, back-EMF still brakes); coast opens it (no torque).
double dc_motor_torque(const MotorDesc& motor, const DcMotorCommand& command, double omega_radps);

// Shaft speed where the motor's torque balances a constant load torque (gear friction included),
// the steady state on level ground with no other losses.
double dc_motor_steady_speed(const MotorDesc& motor, double duty, double load_torque_nm);

}  // namespace sear
