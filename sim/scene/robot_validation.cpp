// Cross-checks of a robot once all its parts are read: names, wiring and the drive layout.
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <unordered_set>

#include "scene/loader_parts.hpp"
#include "scene/nearest_name.hpp"

namespace sear {

void validate_robot(const RobotDesc& robot, Diagnostics& diagnostics) {
  const auto fail = [&](const SourceRef& at, const std::string& message) {
    diagnostics.error(at.file, at.line, fmt::format("robot '{}': {}", robot.name, message));
  };

  // Names are looked up in hash sets, so that checks stay linear however many parts a robot has.
  std::vector<std::string> wheel_names;
  std::unordered_set<std::string> wheel_set;
  for (const auto& w : robot.wheels) {
    if (!wheel_set.insert(w.name).second) fail(w.source, fmt::format("wheel name '{}' is used twice", w.name));
    wheel_names.push_back(w.name);
  }

  // Each wheel is driven by at most one actuator; every actuator names real wheels.
  std::map<std::string, std::string> driven_by;
  std::unordered_set<std::string> actuator_names;
  const auto claim = [&](const SourceRef& at, const std::string& actuator, const std::string& wheel, bool steer) {
    if (!wheel_set.count(wheel)) {
      fail(at, fmt::format("'{}' names unknown wheel '{}'{}", actuator, wheel,
                           did_you_mean(diagnostics, wheel, wheel_names)));
      return;
    }
    const std::string key = (steer ? "steer:" : "drive:") + wheel;
    if (driven_by.count(key))
      fail(at, fmt::format("wheel '{}' is already {} by '{}'", wheel, steer ? "steered" : "driven", driven_by[key]));
    driven_by[key] = actuator;
  };
  const auto name_actuator = [&](const SourceRef& at, const std::string& name) {
    if (!actuator_names.insert(name).second) fail(at, fmt::format("actuator name '{}' is used twice", name));
  };
  for (const auto& m : robot.motors) {
    name_actuator(m.source, m.name);
    for (const auto& w : m.wheels) claim(m.source, m.name, w, false);
  }
  for (const auto& s : robot.servos) {
    name_actuator(s.source, s.name);
    const bool steer = s.kind == ServoDesc::Kind::Positional;
    for (const auto& w : s.wheels) {
      claim(s.source, s.name, w, steer);
      const auto it = std::find_if(robot.wheels.begin(), robot.wheels.end(),
                                   [&](const WheelDesc& wd) { return wd.name == w; });
      if (steer && it != robot.wheels.end() && !it->steered)
        fail(s.source, fmt::format("servo '{}' steers wheel '{}', which is not marked steered=\"true\"", s.name, w));
      if (!steer && it != robot.wheels.end() && it->steered)
        fail(s.source, fmt::format("continuous servo '{}' cannot drive steered wheel '{}'; drive it with a <motor>",
                                   s.name, w));
    }
  }

  const std::size_t steered =
      std::count_if(robot.wheels.begin(), robot.wheels.end(), [](const WheelDesc& w) { return w.steered; });
  const SourceRef& at = robot.parts_source;
  switch (robot.drive) {
    case DriveKind::Differential:
      if (robot.wheels.size() != 2) fail(at, fmt::format("drive=\"differential\" needs 2 wheels, found {}", robot.wheels.size()));
      if (robot.casters.empty()) fail(at, "drive=\"differential\" needs at least one <caster>");
      break;
    case DriveKind::SkidSteer:
      if (robot.wheels.size() != 4) fail(at, fmt::format("drive=\"skid_steer\" needs 4 wheels, found {}", robot.wheels.size()));
      break;
    case DriveKind::Ackermann:
      if (robot.wheels.size() != 4) fail(at, fmt::format("drive=\"ackermann\" needs 4 wheels, found {}", robot.wheels.size()));
      if (steered != 2) fail(at, fmt::format("drive=\"ackermann\" needs 2 wheels with steered=\"true\", found {}", steered));
      else if (robot.wheels.size() == 4) {
        double steered_x = 0, fixed_x = 0;
        for (const auto& w : robot.wheels) (w.steered ? steered_x : fixed_x) += 0.5 * w.position_m.x();
        if (steered_x <= fixed_x) fail(at, "drive=\"ackermann\" steers the front wheels: steered wheels need a larger x");
      }
      break;
  }
  if (robot.drive != DriveKind::Ackermann && steered > 0)
    fail(at, "only drive=\"ackermann\" has steered wheels");
  for (const auto& w : robot.wheels)
    if (w.steered && !driven_by.count("steer:" + w.name))
      fail(w.source, fmt::format("steered wheel '{}' has no positional servo steering it", w.name));

  validate_mcus(robot, diagnostics);
  warn_misplaced_devices(robot, diagnostics);
  std::vector<std::string> motor_names, servo_names;
  for (const auto& m : robot.motors) motor_names.push_back(m.name);
  for (const auto& s : robot.servos) servo_names.push_back(s.name);
  const std::unordered_set<std::string> motor_set(motor_names.begin(), motor_names.end());
  const std::unordered_set<std::string> servo_set(servo_names.begin(), servo_names.end());
  for (const auto& cmd : robot.script) {
    if (!(cmd.is_servo ? servo_set : motor_set).count(cmd.actuator))
      fail(cmd.source, fmt::format("script names unknown {} '{}'{}", cmd.is_servo ? "servo" : "motor", cmd.actuator,
                                   did_you_mean(diagnostics, cmd.actuator, cmd.is_servo ? servo_names : motor_names)));
  }
}

}  // namespace sear
