// Reads <scenario> files and a project's <expect>, element by element with the project loader's
// ElementReader, so that messages and their file:line look the same as the rest of `sear check`.
#include "expect/scenario_loader.hpp"

#include <fmt/format.h>
#include <tinyxml2.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "scene/element_reader.hpp"
#include "scene/loader_parts.hpp"
#include "scene/nearest_name.hpp"
#include "scene/value_ranges.hpp"

namespace sear {
namespace {

// Sim times: a deadline after the start, or an instant that may be the start itself.
const Range kDeadline = Range::above(0, kMaxTime_s, "> 0 and <= 1e7 s");
const Range kInstant = Range::between(0, kMaxTime_s, "0..1e7 s");
const Range kPin = Range::between(0, 69, "0..69 (the Mega 2560's pins; A0..A15 are 54..69)");
const Range kPort = Range::between(0, 3, "0..3");
// A million bytes a second for 116 days (kMaxTime_s) stays below 1e13.
const Range kByteCount = Range::between(1, 1e13, "1..1e13");
const Range kRadius = Range::above(0, 2e5, "> 0 and <= 200000 m");

const std::vector<std::string> kKinds = {"console", "region", "no_collision", "pin", "uart", "mcu_running"};

std::int64_t to_ns(double s) { return static_cast<std::int64_t>(std::llround(s * 1e9)); }

std::optional<std::int64_t> optional_time(ElementReader& r, const char* attribute, const Range& range) {
  if (!r.has(attribute)) return std::nullopt;
  const auto v = r.required_number(attribute, range, "s");
  return v ? std::optional<std::int64_t>(to_ns(*v)) : std::nullopt;
}

std::optional<int> required_index(ElementReader& r, const char* attribute, const Range& range) {
  const auto v = r.required_number(attribute, range);
  if (!v) return std::nullopt;
  if (*v != std::floor(*v)) {
    r.error(fmt::format("<{}> '{}' must be a whole number in {}", r.name(), attribute, range.text));
    return std::nullopt;
  }
  return static_cast<int>(*v);
}

// One of `attributes` exactly; returns its index, or -1 after reporting none or several.
int exactly_one(ElementReader& r, std::initializer_list<const char*> attributes, const char* meaning) {
  int found = -1, count = 0, i = 0;
  std::string list;
  for (const char* a : attributes) {
    if (r.has(a)) {
      found = i;
      ++count;
    }
    list += fmt::format("{}'{}'", list.empty() ? "" : (i + 1 == static_cast<int>(attributes.size()) ? " or " : ", "), a);
    ++i;
  }
  if (count == 1) return found;
  r.error(fmt::format("<{}> needs exactly one of {} ({}), {}", r.name(), list, meaning,
                      count ? "not several" : "and has none"));
  return -1;
}

std::optional<std::string> parse_hex(ElementReader& r, const std::string& text) {
  std::istringstream in(text);
  std::string out;
  for (std::string word; in >> word;) {
    char* end = nullptr;
    const unsigned long v = word.size() == 2 ? std::strtoul(word.c_str(), &end, 16) : 0;
    if (word.size() != 2 || !end || *end) {
      r.error(fmt::format("<uart> 'hex': expected bytes as pairs of hex digits separated by spaces (\"B5 62\"), got '{}'",
                          word));
      return std::nullopt;
    }
    out.push_back(static_cast<char>(v));
  }
  if (out.empty()) r.error("<uart> 'hex' names no bytes");
  return out.empty() ? std::nullopt : std::optional<std::string>(out);
}

void read_console(ElementReader& r, Expectation& e) {
  ConsoleExpect c;
  const int which = exactly_one(r, {"matches", "never"}, "a line that must appear, or one that must not");
  if (which >= 0) {
    c.never = which == 1;
    const char* attribute = c.never ? "never" : "matches";
    c.pattern = r.required_text(attribute).value_or("");
    try {
      c.regex = std::make_shared<const std::regex>(c.pattern, std::regex::ECMAScript);
    } catch (const std::regex_error& error) {
      r.error(fmt::format("<console> '{}': \"{}\" is not an ECMAScript regular expression ({})", attribute, c.pattern,
                          error.what()));
    }
  }
  if (c.never && r.has("before"))
    r.error("<console> 'before' goes with 'matches': a line given by 'never' must not appear at any time");
  else
    e.before_ns = optional_time(r, "before", kDeadline);
  e.what = c;
}

void read_region(ElementReader& r, Expectation& e) {
  RegionExpect g;
  if (!r.has("shape")) r.error("<region> needs attribute 'shape' (circle or box)");
  g.shape = r.choice("shape", {"circle", "box"}, 0) == 0 ? RegionExpect::Shape::Circle : RegionExpect::Shape::Box;
  const bool circle = g.shape == RegionExpect::Shape::Circle;
  const auto point = [&](const char* attribute, bool wanted, Eigen::Vector2d& out) {
    const bool given = r.has(attribute);
    if (given && !wanted)
      r.error(fmt::format("<region> '{}' is for shape=\"{}\"", attribute, circle ? "box" : "circle"));
    else if (!given && wanted)
      r.error(fmt::format("<region> shape=\"{}\" needs attribute '{}' (x y, m)", circle ? "circle" : "box", attribute));
    else if (given)
      out = r.vec2(attribute, out, ranges::kWorldXY);
  };
  point("center", circle, g.center_m);
  point("min", !circle, g.min_m);
  point("max", !circle, g.max_m);
  if (circle) g.radius_m = r.required_number("radius", kRadius, "m").value_or(1.0);
  else if (r.has("radius")) r.error("<region> 'radius' is for shape=\"circle\"");
  if (!circle && r.has("min") && r.has("max") && !(g.min_m.array() < g.max_m.array()).all())
    r.error(fmt::format("<region> 'min' ({} {}) must be below 'max' ({} {}) in x and in y", g.min_m.x(), g.min_m.y(),
                        g.max_m.x(), g.max_m.y()));
  e.before_ns = optional_time(r, "before", kDeadline);
  e.what = g;
}

void read_pin(ElementReader& r, Expectation& e) {
  PinExpect p;
  p.pin = required_index(r, "pin", kPin).value_or(0);
  if (!r.has("level")) r.error("<pin> needs attribute 'level' (0 or 1)");
  p.level = static_cast<int>(r.choice("level", {"0", "1"}, 0));
  const bool at = r.has("at");
  const bool interval = r.has("from") || r.has("to");
  if (at == interval) {
    r.error("<pin> needs either 'at' (an instant, s) or 'from' and 'to' (an interval, s)");
  } else if (at) {
    p.from_ns = p.to_ns = optional_time(r, "at", kInstant).value_or(0);
  } else {
    const auto from = r.required_number("from", kInstant, "s");
    const auto to = r.required_number("to", kDeadline, "s");
    if (from && to && !(*from < *to))
      r.error(fmt::format("<pin> 'from' ({} s) must come before 'to' ({} s); for one instant use 'at'", *from, *to));
    p.from_ns = to_ns(from.value_or(0));
    p.to_ns = to_ns(to.value_or(0));
  }
  e.what = p;
}

void read_uart(ElementReader& r, Expectation& e) {
  UartExpect u;
  u.port = required_index(r, "port", kPort).value_or(0);
  if (!r.has("direction")) r.error("<uart> needs attribute 'direction' (tx: sent by the MCU, rx: arriving at it)");
  u.tx = r.choice("direction", {"tx", "rx"}, 0) == 0;
  switch (exactly_one(r, {"at_least", "contains", "hex"}, "a byte count, or bytes in a row as text or as hex")) {
    case 0:
      u.at_least = static_cast<std::uint64_t>(r.whole_number("at_least", 1, kByteCount));
      break;
    case 1:
      u.pattern = r.required_text("contains").value_or("");
      break;
    case 2:
      u.hex = true;
      u.pattern = parse_hex(r, r.text("hex", "")).value_or("");
      break;
    default:
      break;
  }
  e.before_ns = optional_time(r, "before", kDeadline);
  e.what = u;
}

Expectation read_expectation(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics) {
  ElementReader r(&element, file, diagnostics);
  Expectation e;
  e.source = {file, r.line()};
  const std::string kind = element.Name();
  if (kind == "region" || kind == "no_collision") e.robot = r.required_text("robot").value_or("");
  else e.mcu = r.required_text("mcu").value_or("");
  if (kind == "console") {
    read_console(r, e);
  } else if (kind == "region") {
    read_region(r, e);
  } else if (kind == "no_collision") {
    CollisionExpect c;
    if (r.has("with")) c.with = r.required_text("with").value_or("");
    e.what = c;
  } else if (kind == "pin") {
    read_pin(r, e);
  } else if (kind == "uart") {
    read_uart(r, e);
  } else {
    e.what = RunningExpect{};
  }
  const std::string name = r.text("name", "");
  if (!name.empty()) check_label(r, "name", name);
  e.name = name.empty() ? describe(e) : name;
  r.finish();
  return e;
}

// The latest instant an expectation looks at, for checking it against the timeout.
std::optional<std::int64_t> last_instant(const Expectation& e) {
  if (const auto* p = std::get_if<PinExpect>(&e.what)) return p->to_ns;
  return e.before_ns;
}

void read_expect(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics,
                 Scenario& scenario, bool timeout_here) {
  ElementReader r(&element, file, diagnostics);
  if (timeout_here) {
    const auto timeout = optional_time(r, "timeout", ranges::kDuration);
    if (timeout) scenario.timeout_ns = timeout;
  }
  std::map<std::string, int> lines;
  r.children(kKinds, [&](const tinyxml2::XMLElement& child) {
    Expectation e = read_expectation(child, file, diagnostics);
    const auto [it, fresh] = lines.emplace(e.name, e.source.line);
    if (!fresh)
      diagnostics.error(file, e.source.line,
                        fmt::format("<{}> test case name '{}' is already used on line {}; give one a 'name'",
                                    child.Name(), e.name, it->second));
    const auto last = last_instant(e);
    if (last && scenario.timeout_ns && *last > *scenario.timeout_ns)
      diagnostics.error(file, e.source.line,
                        fmt::format("<{}> looks at {} s, after the timeout ({} s): it could never be met",
                                    child.Name(), static_cast<double>(*last) / 1e9,
                                    static_cast<double>(*scenario.timeout_ns) / 1e9));
    scenario.expectations.push_back(std::move(e));
  });
  if (lines.empty() && !element.FirstChildElement()) r.error("<expect> lists nothing to check");
  r.finish();
}

std::string absolute_path(const std::string& path) {
  return std::filesystem::absolute(path).lexically_normal().string();
}

}  // namespace

std::optional<Scenario> load_scenario_text(const std::string& xml, const std::string& path, Diagnostics& diagnostics) {
  tinyxml2::XMLDocument doc;
  if (!parse_xml(xml, path, diagnostics, doc)) return std::nullopt;
  const tinyxml2::XMLElement* root = doc.RootElement();
  const std::string kind = root ? root->Name() : "";
  Scenario scenario;
  scenario.file = path;
  const std::string stem = std::filesystem::path(path).stem().string();
  if (kind == "project") {
    // The project loader reads and checks everything else in this file; only <expect> is ours.
    const char* name = root->Attribute("name");
    scenario.name = name && *name ? name : stem;
    scenario.project_file = absolute_path(path);
    if (const auto* expect = root->FirstChildElement("expect"))
      read_expect(*expect, path, diagnostics, scenario, true);
  } else if (kind == "scenario") {
    ElementReader r(root, path, diagnostics);
    scenario.name = r.text("name", stem);
    check_label(r, "name", scenario.name);
    if (const auto project = r.required_text("project")) {
      const std::string beside = path_beside(path, *project);
      if (check_readable_file(r, "project file", *project, beside)) scenario.project_file = absolute_path(beside);
    }
    if (r.has("seed"))
      scenario.seed = static_cast<std::uint64_t>(r.whole_number("seed", 1, ranges::kSeed));
    scenario.timeout_ns = optional_time(r, "timeout", ranges::kDuration);
    check_at_most_one(*root, path, diagnostics, {"expect"});
    if (!root->FirstChildElement("expect")) r.error("<scenario> needs an <expect> listing what the run must show");
    r.children({"expect"}, [&](const tinyxml2::XMLElement& expect) {
      if (&expect == root->FirstChildElement("expect")) read_expect(expect, path, diagnostics, scenario, false);
    });
    r.finish();
  } else {
    diagnostics.error(path, root ? root->GetLineNum() : 1,
                      "a scenario file must have <scenario> (or, for a project's own expectations, <project>) as its "
                      "root element");
  }
  if (!diagnostics.ok()) return std::nullopt;
  return scenario;
}

std::optional<Scenario> load_scenario(const std::string& path, Diagnostics& diagnostics) {
  const auto text = read_named_file(path, "project or scenario file", diagnostics);
  return text ? load_scenario_text(*text, path, diagnostics) : std::nullopt;
}

namespace {

const char* element_of(const Expectation& e) { return kKinds[e.what.index()].c_str(); }

}  // namespace

bool check_scenario(const Scenario& scenario, const ProjectDesc& project, Diagnostics& diagnostics) {
  const std::size_t before = diagnostics.count();
  std::vector<std::string> mcu_ids, robots, others;
  std::map<std::string, const McuDesc*> mcus;
  for (const auto& robot : project.robots) {
    robots.push_back(robot.name);
    others.push_back(robot.name);
    for (const auto& mcu : robot.mcus) {
      mcu_ids.push_back(robot.name + "." + mcu.name);
      mcus[mcu_ids.back()] = &mcu;
    }
  }
  for (const auto& b : project.world.boxes) others.push_back(b.name);
  for (const auto& t : project.world.trees) others.push_back(t.name);
  for (const auto& w : project.world.walls) others.push_back(w.name);
  for (const auto& m : project.world.meshes) others.push_back(m.name);
  const auto unknown = [&](const Expectation& e, const char* attribute, const std::string& value,
                           const std::string& what, const std::vector<std::string>& names) {
    diagnostics.error(e.source.file, e.source.line,
                      fmt::format("<{}> {} '{}': the project has no such {}{}", element_of(e), attribute, value, what,
                                  did_you_mean(diagnostics, value, names)));
  };
  for (const auto& e : scenario.expectations) {
    if (!e.mcu.empty()) {
      const auto it = mcus.find(e.mcu);
      if (it == mcus.end()) {
        unknown(e, "mcu", e.mcu, e.mcu.find('.') == std::string::npos ? "MCU (MCUs are named 'robot.mcu')" : "MCU",
                mcu_ids);
      } else if (std::holds_alternative<ConsoleExpect>(e.what) && it->second->console_uart < 0) {
        diagnostics.error(e.source.file, e.source.line,
                          fmt::format("<console> mcu '{}' has no console (its console_uart is -1)", e.mcu));
      }
    }
    if (!e.robot.empty() && std::find(robots.begin(), robots.end(), e.robot) == robots.end())
      unknown(e, "robot", e.robot, "robot", robots);
    if (const auto* c = std::get_if<CollisionExpect>(&e.what))
      if (!c->with.empty() && std::find(others.begin(), others.end(), c->with) == others.end())
        unknown(e, "with", c->with, "obstacle or robot", others);
  }
  return diagnostics.count() == before;
}

}  // namespace sear
