#include <fmt/format.h>

#include "runtime/simulation.hpp"
#include "scene/project_loader.hpp"
#include "sear/commands.hpp"

namespace sear {

int check_command(const std::string& project) {
  Diagnostics diagnostics;
  const std::string path = resolve_project_path(project);
  auto loaded = load_project(path, diagnostics);
  if (!loaded) {
    fmt::print(stderr, "{}", diagnostics.joined());
    fmt::print(stderr, "{}: {} error{}\n", path, diagnostics.all().size(), diagnostics.all().size() == 1 ? "" : "s");
    return 1;
  }
  // Building the world finds what only the world knows, such as a robot placed off the terrain.
  try {
    Simulation world(*loaded, loaded->run.seed);
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
  // Firmware named by its sources must compile: a run would stop there too (and the build is cached).
  try {
    build_project_firmware(*loaded, false);
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
  const auto count = [](std::size_t n, const char* one, const char* many) {
    return fmt::format("{} {}", n, n == 1 ? one : many);
  };
  const WorldDesc& w = loaded->world;
  fmt::print("{}: ok ({}, {}, {}, {}, {})\n", path, count(loaded->robots.size(), "robot", "robots"),
             count(w.boxes.size(), "box", "boxes"), count(w.trees.size(), "tree", "trees"),
             count(w.walls.size(), "wall", "walls"), count(w.meshes.size(), "mesh", "meshes"));
  return 0;
}

}  // namespace sear
