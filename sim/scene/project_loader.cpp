// Reads the project file: its <run> settings, the <world> and the <robot>s.
#include "scene/project_loader.hpp"

#include <fmt/format.h>
#include <tinyxml2.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "scene/element_reader.hpp"
#include "scene/loader_parts.hpp"
#include "scene/value_ranges.hpp"

namespace sear {

std::optional<ProjectDesc> load_project_text(const std::string& xml, const std::string& path,
                                             Diagnostics& diagnostics) {
  // The file's name goes into summary.json as the project's file: JSON holds only UTF-8.
  if (first_invalid_utf8(path) != std::string::npos) {
    diagnostics.error(path, 0, "the project file's name is not valid UTF-8; rename it");
    return std::nullopt;
  }
  if (!check_utf8(xml, path, diagnostics)) return std::nullopt;
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS) {
    diagnostics.error(path, doc.ErrorLineNum(), fmt::format("malformed XML: {}", doc.ErrorStr()));
    return std::nullopt;
  }
  const tinyxml2::XMLElement* root = doc.RootElement();
  if (!root || std::string(root->Name()) != "project") {
    diagnostics.error(path, root ? root->GetLineNum() : 1, "a project file must have <project> as its root element");
    return std::nullopt;
  }

  ProjectDesc project;
  project.file = path;
  ElementReader r(root, path, diagnostics);
  project.name = r.text("name", std::filesystem::path(path).stem().string());
  check_label(r, "name", project.name);

  // The world comes first whatever the order in the file: robots refer to its materials and origin.
  const tinyxml2::XMLElement* world = root->FirstChildElement("world");
  if (!world) r.error("<project> needs a <world>");
  else read_world(*world, path, diagnostics, project.world);

  r.children({"run", "world", "robot"}, [&](const tinyxml2::XMLElement& child) {
    const std::string kind = child.Name();
    if (kind == "world") {
      if (&child != world) diagnostics.error(path, child.GetLineNum(), "a project has one <world>");
    } else if (kind == "run") {
      ElementReader c(&child, path, diagnostics);
      project.run.duration_s = c.number("duration", project.run.duration_s, ranges::kDuration, "s");
      project.run.seed = static_cast<std::uint64_t>(
          c.whole_number("seed", static_cast<double>(project.run.seed), ranges::kSeed));
      project.run.trace_rate_hz = c.number("trace_rate", project.run.trace_rate_hz, ranges::kTraceRate, "Hz");
      c.finish();
    } else {
      RobotDesc robot;
      if (!read_project_robot(child, path, diagnostics, project.world, robot)) return;
      project.robots.push_back(std::move(robot));
    }
  });
  r.finish();
  check_at_most_one(*root, path, diagnostics, {"run"});
  for (const auto& robot : project.robots) validate_robot(robot, diagnostics);

  // Collision reports name what was hit: every obstacle and robot needs a name of its own. A hash
  // map keeps this linear: a generated world of 160 000 boxes is checked in well under a second.
  std::unordered_map<std::string, int> first_line;
  const auto unique = [&](const std::string& name, int line, const std::string& what) {
    const auto [it, fresh] = first_line.emplace(name, line);
    if (!fresh)
      diagnostics.error(path, line,
                        fmt::format("{} name '{}' is already used by another obstacle or robot (line {})", what, name,
                                    it->second));
  };
  for (const auto& b : project.world.boxes) unique(b.name, b.line, "box");
  for (const auto& t : project.world.trees) unique(t.name, t.line, "tree");
  for (const auto& w : project.world.walls) unique(w.name, w.line, "wall");
  for (const auto& m : project.world.meshes) unique(m.name, m.line, "mesh");
  for (const auto& robot : project.robots) unique(robot.name, robot.source.line, "robot");
  if (!diagnostics.ok()) return std::nullopt;
  return project;
}

std::optional<ProjectDesc> load_project(const std::string& path, Diagnostics& diagnostics) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    diagnostics.error(path, 0, std::filesystem::exists(path) ? "cannot read project file" : "project file not found");
    return std::nullopt;
  }
  std::ostringstream text;
  text << in.rdbuf();
  return load_project_text(text.str(), path, diagnostics);
}

}  // namespace sear
