// The world of a run as plain data for tools that draw it (tools/plots/plot_run.py): terrain kind,
// size and a height grid of at most 256 x 256, obstacles with their shapes at their start poses,
// the GPS origin, and each robot's start and its MCUs' wired devices and ADC reference voltages.
#pragma once

#include <string>

#include "scene/description.hpp"

namespace sear {

// Most cells of the height grid along either side; a larger heightmap is sampled down to it.
constexpr int kWorldJsonMaxGrid = 256;

// The JSON text (world x east, y north, metres; "heights_m" row 0 is the north edge).
std::string world_json(const ProjectDesc& project);
// Writes world_json(project) to `path`; throws std::runtime_error naming the file on failure.
void write_world_json(const std::string& path, const ProjectDesc& project);

}  // namespace sear
