#include <fmt/format.h>

#include "scene/project_loader.hpp"
#include "sear/commands.hpp"

namespace sear {

int check_command(const std::string& project) {
  Diagnostics diagnostics;
  const std::string path = resolve_project_path(project);
  const auto loaded = load_project(path, diagnostics);
  if (!loaded) {
    fmt::print(stderr, "{}", diagnostics.joined());
    fmt::print(stderr, "{}: {} error{}\n", path, diagnostics.all().size(), diagnostics.all().size() == 1 ? "" : "s");
    return 1;
  }
  fmt::print("{}: ok ({} robot{}, {} boxes, {} trees, {} walls, {} meshes)\n", path, loaded->robots.size(),
             loaded->robots.size() == 1 ? "" : "s", loaded->world.boxes.size(), loaded->world.trees.size(),
             loaded->world.walls.size(), loaded->world.meshes.size());
  return 0;
}

}  // namespace sear
