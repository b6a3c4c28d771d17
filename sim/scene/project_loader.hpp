// Reads a project file, and the robot files it includes, into a validated ProjectDesc.
#pragma once

#include <optional>
#include <string>

#include "scene/description.hpp"
#include "scene/diagnostics.hpp"

namespace sear {

// Every problem found goes to `diagnostics`; the result is empty if there was any.
std::optional<ProjectDesc> load_project(const std::string& path, Diagnostics& diagnostics);

// The same from text already in memory; `path` names it in messages and anchors relative file names.
std::optional<ProjectDesc> load_project_text(const std::string& xml, const std::string& path,
                                             Diagnostics& diagnostics);

}  // namespace sear
