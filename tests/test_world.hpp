// Helpers for physics tests: projects written inline as XML, loaded as if they sat in
// assets/projects/ so that "../robots/rover.xml" and "../meshes/..." resolve to the bundled files.
#pragma once

#include <functional>
#include <string>

#include "runtime/simulation.hpp"
#include "scene/description.hpp"

namespace sear::test {

// Loads project XML text; fails the calling test (via exception) with every diagnostic if it has errors.
ProjectDesc project_from_xml(const std::string& xml);

// A <project> around `world_children` (inside <world>) and `robots` (after it), with the usual materials.
std::string project_xml(const std::string& world_attributes, const std::string& world_children,
                        const std::string& robots);

// Runs the simulation until `seconds` of sim time have passed, calling `each_step` after every step.
void run_for(Simulation& sim, double seconds, const std::function<void()>& each_step = {});

// Sets every motor of robot 0 to the same command.
void drive(Simulation& sim, const std::string& motor, double duty, MotorDirection direction);

}  // namespace sear::test
