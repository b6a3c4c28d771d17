// Reads what a headless run must show: a scenario file (<scenario project=... seed=... timeout=...>
// with an <expect>), or a project file's own <expect>; then checks the names it uses against the
// loaded project. Errors name the file and line, as the project loader's do.
#pragma once

#include <optional>
#include <string>

#include "expect/expectation.hpp"
#include "scene/diagnostics.hpp"

namespace sear {

// A scenario file, or a project file (a project without <expect> gives no expectations). Every
// problem goes to `diagnostics`; the result is empty if there was any.
std::optional<Scenario> load_scenario(const std::string& path, Diagnostics& diagnostics);

// The same from text in memory; `path` names it in messages and anchors the project's path.
std::optional<Scenario> load_scenario_text(const std::string& xml, const std::string& path,
                                           Diagnostics& diagnostics);

// Robots, MCUs ("robot.mcu"), obstacles and consoles the expectations name exist in `project`.
// False when any does not (each reported with the nearest valid name).
bool check_scenario(const Scenario& scenario, const ProjectDesc& project, Diagnostics& diagnostics);

}  // namespace sear
