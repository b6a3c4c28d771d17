// Reads a moving URDF joint's <limit> and <dynamics> into what the physics honours, with the
// decisions that ODE's hinge forces named.
#include "scene/urdf_joints.hpp"

#include <fmt/format.h>
#include <urdf_model/joint.h>

#include <algorithm>
#include <cmath>

namespace sear {

std::vector<std::string> read_joint_motion(const urdf::Joint& joint, JointLinkDesc& out,
                                           std::vector<std::string>& warnings) {
  std::vector<std::string> problems;
  const bool prismatic = joint.type == urdf::Joint::PRISMATIC;
  out.kind = prismatic ? JointLinkDesc::Kind::Slider : JointLinkDesc::Kind::Hinge;
  out.limited = false;
  if (joint.limits) {
    const auto& l = *joint.limits;
    if (l.effort < 0) problems.push_back(fmt::format("<limit effort=\"{}\"> is negative", l.effort));
    if (l.velocity < 0) problems.push_back(fmt::format("<limit velocity=\"{}\"> is negative", l.velocity));
    out.effort = std::max(0.0, l.effort);
    out.velocity = std::max(0.0, l.velocity);
    if (joint.type != urdf::Joint::CONTINUOUS) {
      if (l.lower > l.upper)
        problems.push_back(fmt::format("<limit lower=\"{}\" upper=\"{}\">: lower is above upper", l.lower, l.upper));
      out.limited = true;
      out.lower = l.lower;
      out.upper = l.upper;
      if (!prismatic && l.upper - l.lower >= 2 * M_PI) {
        // A full turn or more between the stops: nothing stops it, as a continuous joint.
        out.limited = false;
        warnings.push_back(fmt::format("joint '{}': its limits {:.4g}..{:.4g} rad span a full turn: it turns "
                                       "without stops",
                                       joint.name, l.lower, l.upper));
      } else if (!prismatic && (l.lower < -M_PI || l.upper > M_PI)) {
        // ODE measures a hinge's angle in -pi..pi: a stop beyond it would meet the angle wrapped
        // around from the other side and hold the joint at the wrong place.
        warnings.push_back(fmt::format("joint '{}': ODE measures a hinge's angle in -pi..pi, so its stop{} at {} "
                                       "cannot be held and {} left out",
                                       joint.name, l.lower < -M_PI && l.upper > M_PI ? "s" : "",
                                       l.lower < -M_PI && l.upper > M_PI ? fmt::format("{:.4g} and {:.4g} rad", l.lower, l.upper)
                                       : l.lower < -M_PI                 ? fmt::format("{:.4g} rad", l.lower)
                                                                         : fmt::format("{:.4g} rad", l.upper),
                                       l.lower < -M_PI && l.upper > M_PI ? "are" : "is"));
        if (l.lower < -M_PI) out.lower = -INFINITY;
        if (l.upper > M_PI) out.upper = INFINITY;
      }
    }
  }
  if (joint.dynamics) {
    if (joint.dynamics->damping < 0)
      problems.push_back(fmt::format("<dynamics damping=\"{}\"> is negative", joint.dynamics->damping));
    if (joint.dynamics->friction < 0)
      problems.push_back(fmt::format("<dynamics friction=\"{}\"> is negative", joint.dynamics->friction));
    out.damping = std::max(0.0, joint.dynamics->damping);
    out.friction = std::max(0.0, joint.dynamics->friction);
  }
  return problems;
}

std::string describe_joint(const JointLinkDesc& j, const ServoDesc* servo) {
  const bool slider = j.kind == JointLinkDesc::Kind::Slider;
  const char* unit = slider ? "m" : "rad";
  std::string out = fmt::format("  joint {}: a live {} carrying link '{}' ({:.4g} kg), ", j.joint, slider ? "slider" : "hinge",
                                j.link, j.mass_kg);
  if (servo)
    out += fmt::format("turned by servo '{}' ({:.3g} N*m, {:.3g} rad/s)", servo->name, servo->torque_nm, servo->speed_radps);
  else out += "passive";
  if (!j.limited) out += ", no stops";
  else out += fmt::format(", stops {:.4g}..{:.4g} {}", j.lower, j.upper, unit);
  out += fmt::format(", damping {:.3g} {}, friction {:.3g} {}", j.damping, slider ? "N*s/m" : "N*m*s/rad", j.friction,
                     slider ? "N" : "N*m");
  return out;
}

}  // namespace sear
