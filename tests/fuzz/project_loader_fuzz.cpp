// libFuzzer target: any bytes given to the project loader give a project or diagnostics, never a crash.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "scene/loader_parts.hpp"
#include "scene/project_loader.hpp"

namespace {

// What a run writes into summary.json and file names must be UTF-8 without control characters.
bool clean(const std::string& text) {
  if (sear::first_invalid_utf8(text) != std::string::npos) return false;
  for (char c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sear::Diagnostics diagnostics;
  // Relative file names resolve beside the bundled projects, so the seed corpus can include the
  // real robot files, meshes and heightmap.
  const auto project = sear::load_project_text(std::string(reinterpret_cast<const char*>(data), size),
                                               SEAR_FUZZ_PROJECT_PATH, diagnostics);
  if (project.has_value() != diagnostics.ok()) __builtin_trap();  // a result exactly when there are no errors
  // The first errors are kept, the rest only counted.
  if (diagnostics.all().size() != std::min(diagnostics.count(), sear::Diagnostics::kMaxKept)) __builtin_trap();
  for (const auto& d : diagnostics.all())
    if (d.message.empty()) __builtin_trap();  // every error says what is wrong
  if (project) {
    if (!clean(project->name)) __builtin_trap();
    for (const auto& robot : project->robots) {
      if (!clean(robot.name)) __builtin_trap();
      for (const auto& mcu : robot.mcus)
        if (!clean(mcu.name)) __builtin_trap();
    }
    for (const auto& box : project->world.boxes)
      if (!clean(box.name) || !(box.size_m.allFinite() && box.xy_m.allFinite())) __builtin_trap();
    if (!project->world.gravity.allFinite()) __builtin_trap();
  }
  return 0;
}
