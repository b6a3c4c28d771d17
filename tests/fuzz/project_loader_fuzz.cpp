// libFuzzer target: any bytes given to the project loader give a project or diagnostics, never a crash.
#include <cstddef>
#include <cstdint>
#include <string>

#include "scene/project_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sear::Diagnostics diagnostics;
  // Relative file names resolve beside the bundled projects, so the seed corpus can include the
  // real robot files, meshes and heightmap.
  const auto project = sear::load_project_text(std::string(reinterpret_cast<const char*>(data), size),
                                               SEAR_FUZZ_PROJECT_PATH, diagnostics);
  if (project.has_value() != diagnostics.ok()) __builtin_trap();  // a result exactly when there are no errors
  for (const auto& d : diagnostics.all())
    if (d.message.empty()) __builtin_trap();  // every error says what is wrong
  return 0;
}
