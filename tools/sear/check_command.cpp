#include <fmt/format.h>

#include <sstream>

#include "expect/scenario_loader.hpp"
#include "runtime/simulation.hpp"
#include "scene/project_loader.hpp"
#include "sear/commands.hpp"
#include "sear/urdf_options.hpp"

namespace sear {
namespace {

void print_count(const std::string& path, std::size_t errors) {
  fmt::print(stderr, "{}: {} error{}\n", path, errors, errors == 1 ? "" : "s");
}

// What importing each URDF decided: every mesh's extent in metres (a wrong
// unit shows at once: a 0.3 m chassis read as 300 m) with what became of it.
void print_urdf_imports(const ProjectDesc& project) {
  for (const auto& robot : project.robots) {
    if (robot.urdf.file.empty()) continue;
    fmt::print("robot '{}' from {}: {:.4g} kg, {} wheel{}, {} caster{}, {} collision shape{} on the chassis\n", robot.name,
               robot.urdf.file, robot.chassis.mass_kg, robot.wheels.size(), robot.wheels.size() == 1 ? "" : "s",
               robot.casters.size(), robot.casters.size() == 1 ? "" : "s", robot.chassis.parts.size(),
               robot.chassis.parts.size() == 1 ? "" : "s");
    for (const auto& m : robot.urdf.meshes)
      fmt::print("  {} {} {}: {:.4g} x {:.4g} x {:.4g} m, {} triangles: {}\n", m.link, m.use, m.file, m.extent_m.x(),
                 m.extent_m.y(), m.extent_m.z(), m.triangles, m.decision);
    for (const auto& line : robot.urdf.joints) fmt::print("{}\n", line);
  }
}

}  // namespace

std::vector<std::pair<SourceRef, std::string>> print_import_warnings(const ProjectDesc& project) {
  std::vector<std::pair<SourceRef, std::string>> all;
  for (const auto& robot : project.robots)
    for (const auto& [at, text] : robot.urdf.warnings) {
      fmt::print(stderr, "{}:{}: warning: {}\n", at.file, at.line, text);
      all.emplace_back(at, text);
    }
  return all;
}

std::size_t print_world_errors(const std::string& path, const std::string& text) {
  Diagnostics placement;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) placement.error(path, 0, line);
  for (const auto& d : placement.all()) fmt::print(stderr, "{}\n", d.message);
  if (placement.count() > placement.all().size())
    fmt::print(stderr, "... and {} more errors\n", placement.count() - placement.all().size());
  return placement.count();
}

int check_command(const std::string& project, const std::vector<std::string>& packages,
                  const std::vector<std::string>& args) {
  Diagnostics diagnostics;
  // A scenario names its project; a project is checked with its own <expect>, if any.
  const std::string argument = resolve_project_path(project);
  const auto scenario = load_scenario(argument, diagnostics);
  const std::string path = scenario ? scenario->project_file : argument;
  auto loaded = scenario ? load_project(path, diagnostics, urdf_overrides(packages, args)) : std::nullopt;
  fmt::print(stderr, "{}", diagnostics.warnings_joined());
  if (!loaded || !check_scenario(*scenario, *loaded, diagnostics)) {
    fmt::print(stderr, "{}", diagnostics.joined());
    print_count(argument, diagnostics.count());
    return 1;
  }
  // Building the world finds what only the world knows, such as a robot placed off the terrain.
  // It reports one "file:line: error: ..." line per problem; they go through Diagnostics too, so
  // that 160 000 obstacles off the terrain print a hundred lines and a count.
  try {
    Simulation world(*loaded, loaded->run.seed);
  } catch (const std::exception& e) {
    print_count(path, print_world_errors(path, e.what()));
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
  print_import_warnings(*loaded);
  print_urdf_imports(*loaded);
  const WorldDesc& w = loaded->world;
  fmt::print("{}: ok ({}, {}, {}, {}, {})\n", path, count(loaded->robots.size(), "robot", "robots"),
             count(w.boxes.size(), "box", "boxes"), count(w.trees.size(), "tree", "trees"),
             count(w.walls.size(), "wall", "walls"), count(w.meshes.size(), "mesh", "meshes"));
  return 0;
}

}  // namespace sear
