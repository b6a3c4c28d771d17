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

// The same torque-speed line written as T = damping * (target - omega): a viscous coupling of
// the shaft to the speed it would reach unloaded. In that form a physics engine can apply it
// implicitly, at the speed the shaft has at the end of the step, which is stable for any
// damping against any inertia and step; evaluated at the start of the step instead, a strong
// slow gearmotor on a light wheel (damping * step > 2 * inertia) would oscillate and diverge.
struct DcMotorDrive {
  bool engaged = false;        // false: bridge open (coast), no torque at any speed
  double target_radps = 0;     // duty * free speed at the supply voltage, signed; 0 when braking
  double damping_nmps = 0;     // stall torque / free speed, N*m per rad/s, the same at any voltage
};
DcMotorDrive dc_motor_drive(const MotorDesc& motor, const DcMotorCommand& command);

// Shaft speed where the motor's torque balances a constant load torque (gear friction included),
// the steady state on level ground with no other losses.
double dc_motor_steady_speed(const MotorDesc& motor, double duty, double load_torque_nm);

}  // namespace sear
