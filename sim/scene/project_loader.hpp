// Reads a project file, and the robot files it includes, into a validated ProjectDesc.
#pragma once

#include <optional>
#include <string>

#include "scene/description.hpp"
#include "scene/diagnostics.hpp"
#include "scene/urdf_overrides.hpp"

namespace sear {

// Every problem found goes to `diagnostics`; the result is empty if there was any. `overrides`
// (the command line's --package and --arg) join every URDF robot's mapping.
std::optional<ProjectDesc> load_project(const std::string& path, Diagnostics& diagnostics,
                                        const UrdfOverrides& overrides = {});

// The same from text already in memory; `path` names it in messages and anchors relative file names.
std::optional<ProjectDesc> load_project_text(const std::string& xml, const std::string& path,
                                             Diagnostics& diagnostics, const UrdfOverrides& overrides = {});

}  // namespace sear
