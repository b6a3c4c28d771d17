// The default project with its rover driving straight on a script instead of its firmware, the
// world both benchmarks step.
#pragma once

#include <stdexcept>

#include "scene/project_loader.hpp"

namespace sear::bench {

inline ProjectDesc driving_default_project(double duty) {
  Diagnostics diagnostics;
  auto project = load_project(SEAR_DEFAULT_PROJECT, diagnostics);
  if (!project) throw std::runtime_error(diagnostics.joined());
  auto& rover = project->robots.at(0);
  rover.mcus.clear();
  for (const char* motor : {"left", "right"}) {
    ScriptCommand c;
    c.actuator = motor;
    c.duty = duty;
    c.direction = MotorDirection::Forward;
    rover.script.push_back(c);
  }
  return *project;
}

}  // namespace sear::bench
