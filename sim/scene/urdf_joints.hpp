// A URDF joint that moves and is no wheel, as SEAR simulates it: its kind, stops, effort and
// velocity caps, damping and friction read from the URDF, and the line `sear check` prints for it.
#pragma once

#include <string>
#include <vector>

#include "scene/description.hpp"

namespace urdf {
class Joint;
}

namespace sear {

// Fills `out`'s kind, stops, caps, damping and friction from `joint` (revolute, continuous or
// prismatic). Returns the reasons it cannot be simulated (empty when it can); notes on what was
// decided (a stop ODE cannot hold) go to `warnings`.
std::vector<std::string> read_joint_motion(const urdf::Joint& joint, JointLinkDesc& out,
                                           std::vector<std::string>& warnings);

// "pan_joint: revolute, a live hinge turned by servo 'pan' (...), stops -1.57..1.57 rad, ...".
std::string describe_joint(const JointLinkDesc& joint, const ServoDesc* servo);

}  // namespace sear
