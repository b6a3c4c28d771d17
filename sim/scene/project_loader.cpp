// Reads the project file: its <run> settings, the <world> and the <robot>s.
#include "scene/project_loader.hpp"

#include <fmt/format.h>
#include <tinyxml2.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>

#include "lockstep_link.h"
#include "scene/element_reader.hpp"
#include "scene/loader_parts.hpp"
#include "scene/nearest_name.hpp"
#include "scene/value_ranges.hpp"

namespace sear {
namespace {

const std::vector<std::uint32_t> kCanBitrates = {SEAR_CAN_BITRATES};

CanBusDesc read_can_bus(const tinyxml2::XMLElement& element, const std::string& path, Diagnostics& diagnostics) {
  ElementReader c(&element, path, diagnostics);
  CanBusDesc bus;
  bus.source = {path, c.line()};
  bus.name = c.required_text("name").value_or("");
  check_name(c, bus.name);
  const double rate = c.whole_number("bitrate", bus.bitrate, Range::between(10000, 1000000, "10000..1000000"));
  if (std::find(kCanBitrates.begin(), kCanBitrates.end(), static_cast<std::uint32_t>(rate)) == kCanBitrates.end())
    c.error(fmt::format("<can_bus> 'bitrate' {} is not a rate a CAN controller makes; use 10000, 20000, 50000, "
                        "100000, 125000, 250000, 500000 or 1000000",
                        rate));
  bus.bitrate = static_cast<std::uint32_t>(rate);
  // Up to 1 kHz: at most once a step of the default 1 ms.
  bus.broadcast_hz = c.number("broadcast_hz", 0.0, Range::between(0, 1000, "0..1000 (0: none)"), "Hz");
  c.finish();
  return bus;
}

// Bus names are unique, and every <can bus> names one.
void check_can_buses(const ProjectDesc& project, Diagnostics& diagnostics) {
  std::vector<std::string> names;
  for (const auto& bus : project.can_buses) {
    if (std::find(names.begin(), names.end(), bus.name) != names.end())
      diagnostics.error(bus.source.file, bus.source.line, fmt::format("can_bus name '{}' is used twice", bus.name));
    names.push_back(bus.name);
    // SEAR's broadcast puts the robot's index in the low 4 bits of its identifiers.
    if (bus.broadcast_hz > 0 && project.robots.size() > 16)
      diagnostics.error(bus.source.file, bus.source.line,
                        fmt::format("can_bus '{}' broadcasts the state of at most 16 robots; the project has {}",
                                    bus.name, project.robots.size()));
  }
  for (const auto& robot : project.robots)
    for (const auto& mcu : robot.mcus)
      if (!mcu.can_bus.empty() && std::find(names.begin(), names.end(), mcu.can_bus) == names.end())
        diagnostics.error(mcu.can_source.file, mcu.can_source.line,
                          fmt::format("robot '{}': mcu '{}' is on CAN bus '{}', but the project has no <can_bus "
                                      "name=\"{}\">{}",
                                      robot.name, mcu.name, mcu.can_bus, mcu.can_bus,
                                      did_you_mean(diagnostics, mcu.can_bus, names)));
}

// A kept EEPROM without a file of its own is ROBOT.MCU.eeprom beside the project file, which
// outlives the run's output folder; no two MCUs keep theirs in one file.
void place_eeproms(ProjectDesc& project, Diagnostics& diagnostics) {
  std::map<std::string, std::string> owner;
  const auto folder = std::filesystem::absolute(project.file).parent_path();
  for (auto& robot : project.robots) {
    for (auto& mcu : robot.mcus) {
      if (!mcu.eeprom_persist) continue;
      const std::string id = robot.name + "." + mcu.name;
      if (mcu.eeprom_file.empty()) mcu.eeprom_file = (folder / (id + ".eeprom")).lexically_normal().string();
      const auto [it, fresh] = owner.emplace(mcu.eeprom_file, id);
      if (!fresh)
        diagnostics.error(mcu.eeprom_source.file, mcu.eeprom_source.line,
                          fmt::format("mcu {} keeps its EEPROM in {}, as mcu {} does; give each its own <eeprom file>",
                                      id, mcu.eeprom_file, it->second));
    }
  }
}

}  // namespace

std::optional<ProjectDesc> load_project_text(const std::string& xml, const std::string& path,
                                             Diagnostics& diagnostics, const UrdfOverrides& overrides) {
  // The file's name goes into summary.json as the project's file: JSON holds only UTF-8.
  if (first_invalid_utf8(path) != std::string::npos) {
    diagnostics.error(path, 0, "the project file's name is not valid UTF-8; rename it");
    return std::nullopt;
  }
  tinyxml2::XMLDocument doc;
  if (!parse_xml(xml, path, diagnostics, doc)) return std::nullopt;
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

  // <expect> holds what a headless run checks: read by tools/expect, not here.
  r.children({"run", "world", "robot", "can_bus", "expect"}, [&](const tinyxml2::XMLElement& child) {
    const std::string kind = child.Name();
    if (kind == "expect") {
      return;
    } else if (kind == "can_bus") {
      project.can_buses.push_back(read_can_bus(child, path, diagnostics));
    } else if (kind == "world") {
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
      if (!read_project_robot(child, path, diagnostics, project.world, robot, overrides)) return;
      project.robots.push_back(std::move(robot));
    }
  });
  r.finish();
  check_at_most_one(*root, path, diagnostics, {"run", "expect"});
  for (const auto& robot : project.robots) validate_robot(robot, diagnostics);
  check_can_buses(project, diagnostics);
  place_eeproms(project, diagnostics);

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

std::optional<ProjectDesc> load_project(const std::string& path, Diagnostics& diagnostics,
                                        const UrdfOverrides& overrides) {
  const auto text = read_named_file(path, "project file", diagnostics);
  return text ? load_project_text(*text, path, diagnostics, overrides) : std::nullopt;
}

}  // namespace sear
