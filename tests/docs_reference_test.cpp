// The reference pages name every option and element the code accepts, and nothing it does not.
// Options come from each `sear` command's --help, which CLI11 prints from the very App it parses
// with; elements and attributes from the loaders' own lists of valid names, the ones `sear check`
// prints after an unknown name ("...; valid: a, b"), drawn out by probe files that carry one
// unknown attribute (or child) on every element.
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "command_output.hpp"
#include "expect/scenario_loader.hpp"
#include "firmware_run.hpp"
#include "scene/project_loader.hpp"

namespace sear::test {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = fs::path(SEAR_ASSET_DIR) / "..";

std::string page(const std::string& name) {
  const std::string text = read_file(kSource / "docs" / name);
  EXPECT_FALSE(text.empty()) << "docs/" << name << " is missing or empty";
  return text;
}

std::vector<std::string> matches(const std::string& text, const std::regex& pattern, int group = 1) {
  std::vector<std::string> out;
  for (std::sregex_iterator it(text.begin(), text.end(), pattern), end; it != end; ++it) out.push_back((*it)[group]);
  return out;
}

std::string join(const std::set<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : " ") + n;
  return out;
}

// ---- `sear` and its commands ------------------------------------------------------------------

std::string help(const std::string& command) {
  const CommandOutput run = command_output(std::string(SEAR_BINARY) + " " + command + " --help");
  EXPECT_EQ(run.exit_code, 0) << "sear " << command << " --help";
  return run.out;
}

// The commands `sear --help` lists under "Subcommands:".
std::vector<std::string> commands() {
  const std::string text = help("");
  const auto from = text.find("\nSubcommands:\n");
  if (from == std::string::npos) return {};
  return matches(text.substr(from), std::regex(R"(\n  ([a-z]+) )"));
}

// Each option of a command with all its names ("-d", "--duration"), as its --help lists them:
// "  -d,--duration FLOAT:...", "  --no-plots{false} ...". -h/--help, which CLI11 gives every
// command, is left out: the page says so once.
std::vector<std::set<std::string>> options_of(const std::string& command) {
  std::vector<std::set<std::string>> out;
  for (const std::string& spec : matches(help(command), std::regex(R"(\n  (-[-\w,]+))"))) {
    std::set<std::string> names;
    std::stringstream in(spec);
    for (std::string name; std::getline(in, name, ',');) names.insert(name);
    if (!names.count("--help")) out.push_back(names);
  }
  return out;
}

// Option names written in text: --long-name, and -x standing alone.
std::set<std::string> option_names(const std::string& text) {
  std::set<std::string> out;
  for (const auto& n : matches(text, std::regex(R"((?:^|[\s\[|`(])(--[a-z][a-z0-9-]*|-[a-zA-Z])(?=$|[\s\]|`=,.):]))")))
    out.insert(n);
  return out;
}

// The synopsis at the top of docs/cli.md, per command: "sear run ..." and the lines that continue it.
std::map<std::string, std::string> synopsis(const std::string& cli) {
  std::map<std::string, std::string> out;
  const auto from = cli.find("```\nsear ");
  if (from == std::string::npos) return out;
  const std::string block = cli.substr(from + 4, cli.find("```", from + 4) - from - 4);
  std::string current;
  std::stringstream in(block);
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_search(line, m, std::regex(R"(^sear ([a-z]+))"))) current = m[1];
    out[current] += line + "\n";
  }
  return out;
}

TEST(DocsReference, TheSynopsisOfEachCommandListsExactlyTheOptionsItAccepts) {
  const std::string cli = page("cli.md");
  const auto lines = synopsis(cli);
  const auto names = commands();
  EXPECT_GE(names.size(), 6u);  // run, view, check, sensors, test, new: the pattern still finds them
  for (const std::string& command : names) {
    SCOPED_TRACE("sear " + command);
    ASSERT_TRUE(lines.count(command)) << "docs/cli.md's synopsis has no line for `sear " << command << "`";
    const std::set<std::string> written = option_names(lines.at(command));
    std::set<std::string> accepted;
    for (const auto& option : options_of(command)) {
      accepted.insert(option.begin(), option.end());
      // Every name of it, short and long, so that `-d` in an example means what the page says.
      for (const auto& name : option)
        EXPECT_TRUE(written.count(name)) << "`sear " << command << "` accepts " << name
                                         << ", which its synopsis in docs/cli.md does not list";
    }
    for (const auto& name : written)
      EXPECT_TRUE(accepted.count(name)) << "docs/cli.md's synopsis gives `sear " << command << "` " << name
                                        << ", which it does not accept (it accepts: " << join(accepted) << ")";
  }
}

// Anywhere on the page, an option of `sear` is one some command accepts. Command lines of other
// programs the page shows (cmake in `sear new`'s example) are left out: a code line's segment
// counts only when it runs sear.
TEST(DocsReference, EveryOptionTheCliPageNamesExists) {
  std::set<std::string> accepted{"--help", "-h"};
  for (const std::string& command : commands())
    for (const auto& option : options_of(command)) accepted.insert(option.begin(), option.end());

  const std::string cli = page("cli.md");
  std::string sear_text, last_program;
  bool code = false;
  std::stringstream in(cli);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("```", 0) == 0) {
      code = !code;
      continue;
    }
    if (!code) {
      // Prose: inline code spans that start with an option or with `sear`.
      for (const auto& span : matches(line, std::regex("`([^`]+)`")))
        if (span[0] == '-' ? span.rfind("-D", 0) != 0 : span.rfind("sear ", 0) == 0) sear_text += " " + span + "\n";
      continue;
    }
    // Code: each command of a line (split at &&, ;, a pipe " | " and #) that is sear's, or continues
    // one; "a|b" is a choice within one.
    std::stringstream parts(std::regex_replace(line, std::regex(R"(&&|;| \| |#.*)"), "\n"));
    for (std::string part; std::getline(parts, part);) {
      std::smatch m;
      // A segment that starts with an option, a [bracket] or a PLACEHOLDER goes on with the
      // command before it: `[-d|--duration S]` is one of sear's, not a program of its own.
      if (std::regex_search(part, m, std::regex(R"(^\s*([a-z$./"][^\s\]]*)(\s|$))"))) last_program = m[1];
      if (fs::path(last_program).filename() == "sear") sear_text += " " + part + "\n";
    }
  }
  const std::set<std::string> named = option_names(sear_text);
  EXPECT_GE(named.size(), 40u);  // the page's options are still found
  for (const auto& name : named)
    EXPECT_TRUE(accepted.count(name)) << "docs/cli.md names " << name << ", which no sear command accepts";
}

// ---- Project, robot, mapping and scenario files ---------------------------------------------

// Where an element is read: its element path ("project/robot/mcu/motor"); a robot imported from a
// URDF is "robot@urdf", as its mapping has a page of its own.
using Path = std::vector<std::string>;
const char* const kUrdfRobot = "robot@urdf";

std::string bare(const std::string& element) { return element == kUrdfRobot ? "robot" : element; }

struct Accepted {
  std::map<Path, std::set<std::string>> attributes;  // per element path, the union over probes
  std::map<Path, std::set<std::string>> children;
  std::set<Path> reported;  // elements that refused the probe attribute
  std::set<Path> probed;
};

const char* const kProbe = "docs_probe";

// Every element of `doc`, with its path.
void each_element(tinyxml2::XMLElement* e, Path path, const std::function<void(tinyxml2::XMLElement*, const Path&)>& f) {
  path.push_back(std::string(e->Name()) == "robot" && e->Attribute("urdf") ? kUrdfRobot : e->Name());
  f(e, path);
  for (auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) each_element(c, path, f);
}

// The files of one probe, written with the probe attribute (or child) on every element; loads the
// main file with the project loader and the scenario loader, and gathers what they call valid.
void probe(const std::map<std::string, std::string>& files, const std::string& main, bool children, Accepted& out) {
  TempDir dir;
  std::map<std::pair<std::string, int>, Path> at;  // (file, line) -> element
  for (const auto& [name, raw] : files) {
    if (fs::path(name).extension() != ".xml") {
      std::ofstream(dir.path() / name) << raw;
      continue;
    }
    std::string text = std::regex_replace(raw, std::regex("@ASSETS@"), SEAR_ASSET_DIR);
    text = std::regex_replace(text, std::regex("@DIR@"), dir.path().string());
    tinyxml2::XMLDocument doc;
    ASSERT_EQ(doc.Parse(text.c_str()), tinyxml2::XML_SUCCESS) << name;
    std::vector<tinyxml2::XMLElement*> all;
    each_element(doc.RootElement(), {}, [&](tinyxml2::XMLElement* e, const Path&) { all.push_back(e); });
    for (auto* e : all) {
      if (children) e->InsertEndChild(doc.NewElement(kProbe));
      else e->SetAttribute(kProbe, "1");
    }
    tinyxml2::XMLPrinter printer;
    doc.Print(&printer);
    const std::string path = (dir.path() / name).string();
    std::ofstream(path) << printer.CStr();
    tinyxml2::XMLDocument printed;
    printed.Parse(printer.CStr());
    // An unknown attribute is reported at its element's line, an unknown child at the child's:
    // either way the line names the element the probe was put on.
    each_element(printed.RootElement(), {}, [&](tinyxml2::XMLElement* e, const Path& p) {
      if (p.back() != kProbe) {
        out.probed.insert(p);
        if (!children) at[{path, e->GetLineNum()}] = p;
      } else {
        at[{path, e->GetLineNum()}] = Path(p.begin(), p.end() - 1);
      }
    });
  }
  const std::string main_path = (dir.path() / main).string();
  Diagnostics project_errors, scenario_errors;
  if (files.at(main).find("<scenario") == std::string::npos) (void)load_project(main_path, project_errors);
  (void)load_scenario(main_path, scenario_errors);
  const std::regex attribute(std::string("^unknown attribute '") + kProbe + R"(' on <(\w+)>.*?(?:; valid: (.*))?$)");
  const std::regex child(std::string("^unknown element <") + kProbe + R"(> in <(\w+)>.*?(?:; valid: (.*))?$)");
  for (const Diagnostics* d : {&project_errors, &scenario_errors}) {
    ASSERT_LT(d->all().size(), Diagnostics::kMaxKept) << "a probe gives too many errors to see them all";
    for (const Diagnostic& e : d->all()) {
      std::smatch m;
      const bool is_attribute = std::regex_search(e.message, m, attribute);
      if (!is_attribute && !std::regex_search(e.message, m, child)) continue;
      const auto where = at.find({e.file, e.line});
      ASSERT_NE(where, at.end()) << "no probe element at " << e.str();
      ASSERT_EQ(bare(where->second.back()), m[1]) << e.str();
      auto& names = (is_attribute ? out.attributes : out.children)[where->second];
      if (is_attribute) out.reported.insert(where->second);
      for (const std::string& n : matches(m[2].str(), std::regex(R"(<?([\w]+)>?(?:, |$))"))) names.insert(n);
    }
  }
}

// A world with every element and attribute; `terrain` varies, as each type asks for others.
std::string world_probe(const std::string& terrain) {
  return R"(<project name="probe">
  <run duration="1" seed="1" trace_rate="10"/>
  <world gravity="0 0 -9.81" step="0.001" solver="iterative" solver_iterations="20">
    <gps_origin latitude="52.2" longitude="0.12" altitude="10"/>
    <magnetic declination_deg="1" inclination_deg="60" intensity_nt="49000" year="2026"/>
    <material name="grass" friction="0.7" bounce="0"/>
    )" + terrain + R"(
    <box name="crate" pos="3 0" z="0.2" size="0.5 0.5 0.4" yaw_deg="20" mass="1" material="grass"/>
    <tree name="oak" pos="-3 -3" trunk_radius="0.15" trunk_height="2" crown_radius="1" material="grass"/>
    <wall name="north" from="-6 6" to="6 6" height="0.6" thickness="0.15" material="grass"/>
    <mesh name="rock" file="@ASSETS@/meshes/rock.obj" pos="2 3" yaw_deg="35" scale="1" up_axis="z" material="grass"/>
  </world>
  <can_bus name="body" bitrate="500000" broadcast_hz="10"/>
</project>
)";
}

// A robot's parts, inline in a project or in a robot file.
const char* const kParts = R"(
    <material name="tyre" friction="1" bounce="0"/>
    <chassis shape="box" size="0.3 0.2 0.1" mass="2" material="tyre"/>
    <wheel name="left" pos="0 0.12 0" radius="0.05" width="0.02" mass="0.1" steered="false" material="tyre"/>
    <wheel name="right" pos="0 -0.12 0" radius="0.05" width="0.02" mass="0.1" material="tyre"/>
    <caster pos="-0.1 0 -0.03" radius="0.02"/>
    <motor name="left" wheels="left" stall_torque="0.5" no_load_rpm="100" rated_voltage="6" supply_voltage="6" gear_friction="0.01"/>
    <motor name="right" wheels="right" stall_torque="0.5" no_load_speed="10"/>)";

const char* const kScript = R"(
    <script>
      <motor t="0" name="left" duty="0.5" dir="forward"/>
      <servo t="1" name="pan" pulse_us="1500"/>
    </script>)";

// An MCU with every element an <mcu> holds but the devices (their reference is generated from the
// loader's table, and sensors_command_test holds it to the table).
std::string mcu_probe(const std::string& firmware) {
  return R"(
    <mcu name="main" engine="native" clock_hz="16e6" hal_call_cycles="50" avcc="5" aref="3.3" console_uart="0">
      )" + firmware + R"(
      <motor name="left" pwm="3" dir="12" brake="9" reversed="false"/>
      <servo name="pan" pin="5"/>
      <uart port="1" loopback="true"/>
      <uart port="2" receive="@DIR@/capture.log"/>
      <can bus="body"/>
      <eeprom persist="false"/>
    </mcu>)";
}

Accepted accepted_names() {
  Accepted out;
  const std::string capture = "# a capture\n# time_s direction value\n";
  std::vector<std::pair<std::map<std::string, std::string>, std::string>> probes;
  for (const char* terrain :
       {R"(<terrain type="heightmap" image="@ASSETS@/heightmaps/hills.png" size="40 40" min_height="0" max_height="1" material="grass"/>)",
        R"(<terrain type="mesh" file="@ASSETS@/meshes/rock.obj" scale="1" up_axis="y" material="grass"/>)",
        R"(<terrain type="flat" material="grass"/>)"})
    probes.push_back({{{"project.xml", world_probe(terrain)}}, "project.xml"});

  // A robot written in the project, with a continuous servo and firmware from sources.
  const std::string world = R"(<world><terrain type="flat"/></world>
  <can_bus name="body"/>)";
  probes.push_back({{{"project.xml", "<project name=\"probe\">" + world + R"(
  <robot name="inline" drive="differential">
    <pose x="0" y="0" yaw_deg="0"/>)" + kParts + R"(
    <servo name="pan" kind="continuous" wheels="left" min_pulse_us="1000" max_pulse_us="2000" torque="0.3" no_load_rpm="60"/>)" +
                                       kScript + mcu_probe(R"(<firmware sources="main.c" defines="A=1" includes="." flags="-O1" c_std="c99" cxx_std="c++17"/>)") + R"(
  </robot>
</project>)"},
                     {"main.c", "int main(void) { return 0; }\n"},
                     {"capture.log", capture}},
                    "project.xml"});
  // A robot file (positional servo, mesh chassis), included with a pose by latitude and the other
  // kinds of firmware.
  probes.push_back({{{"project.xml", "<project name=\"probe\">" + world + R"(
  <robot file="robot.xml" name="included">
    <pose latitude="0" longitude="0" yaw_deg="10"/>)" + kScript +
                                       mcu_probe(R"(<firmware sketch="@ASSETS@/../firmware_examples/arduino/avoider_sketch" libraries="."/>)") + R"(
    <mcu name="second" engine="avr"><firmware elf="@DIR@/capture.log"/></mcu>
    <mcu name="third"><firmware executable="/bin/true"/></mcu>
  </robot>
</project>)"},
                     {"robot.xml", R"(<robot name="car" drive="ackermann">
    <material name="tyre" friction="1"/>
    <chassis shape="mesh" file="@ASSETS@/meshes/rover_chassis.obj" scale="1" up_axis="z" mass="2" material="tyre"/>
    <wheel name="left" pos="0.1 0.12 0" radius="0.05" width="0.02" mass="0.1" steered="true" material="tyre"/>
    <servo name="pan" kind="positional" steers="left" min_pulse_us="1000" max_pulse_us="2000" range_deg="60" speed_s_per_60deg="0.17" torque="0.3"/>)" +
                                     std::string(kScript) + R"(
</robot>)"},
                     {"capture.log", capture}},
                    "project.xml"});
  // A robot from its URDF, with every mapping element, some of them in a mapping file.
  probes.push_back({{{"project.xml", "<project name=\"probe\">" + world + R"(
  <robot name="diffbot" urdf="@ASSETS@/robots/diffbot.urdf" drive="differential" mapping="mapping.xml">
    <pose x="0" y="0"/>
    <package name="diffbot" dir="@ASSETS@"/>
    <arg name="a" value="1"/>
    <material name="rubber" friction="1.0"/>
    <chassis material="rubber"/>
    <wheel name="left" joint="left_wheel_joint" material="rubber"/>
    <wheel name="right" joint="right_wheel_joint" material="rubber"/>
    <caster link="caster_link" radius="0.02"/>
    <freeze joint="left_wheel_joint" position="0"/>
    <density link="base_link" kg_per_m3="1000"/>
    <collision link="base_link" max_triangles="1000" replace="box"/>
    <motor name="left" wheels="left" stall_torque="0.6" no_load_rpm="160"/>
    <servo name="pan" kind="continuous" wheels="right" no_load_rpm="60"/>)" + kScript + R"(
    <mcu name="main"><firmware executable="/bin/true"/><gp2d12 name="ir" adc="0"/></mcu>
    <mount device="ir" mcu="main" link="ir_left_link" pos="0 0 0" yaw_deg="0" pitch_deg="0" roll_deg="0"/>
  </robot>
</project>)"},
                     {"mapping.xml", R"(<urdf_mapping drive="differential">
  <package name="other" dir="."/>
  <arg name="b" value="2"/>
  <material name="steel" friction="0.5"/>
  <chassis material="steel"/>
  <wheel name="w" joint="right_wheel_joint"/>
  <caster link="caster_link"/>
  <freeze joint="right_wheel_joint"/>
  <density kg_per_m3="900"/>
  <collision max_triangles="100"/>
  <motor name="m" wheels="w" stall_torque="0.6" no_load_rpm="160"/>
  <servo name="s" kind="positional" steers="w"/>
</urdf_mapping>)"}},
                    "project.xml"});
  // What runs must show: a scenario file, and a project's own <expect>, with every kind in each
  // of its forms.
  const std::string expect = R"(
  <expect timeout="30">
    <console name="a" mcu="rover.main" matches="ready" before="5"/>
    <console mcu="rover.main" never="fault"/>
    <region robot="rover" shape="circle" center="2 1.5" radius="0.5" before="20"/>
    <region robot="rover" shape="box" min="-1 -1" max="1 1"/>
    <no_collision robot="rover" with="crate"/>
    <pin mcu="rover.main" pin="13" level="1" at="2.5"/>
    <pin mcu="rover.main" pin="13" level="0" from="1" to="2"/>
    <uart mcu="rover.main" port="3" direction="rx" at_least="10" before="10"/>
    <uart mcu="rover.main" port="3" direction="tx" contains="$GPGGA"/>
    <uart mcu="rover.main" port="3" direction="tx" hex="B5 62"/>
    <mcu_running mcu="rover.main"/>
  </expect>)";
  probes.push_back({{{"scenario.xml", R"(<scenario name="s" project="project.xml" seed="7" timeout="30">)" + expect + "\n</scenario>"},
                     {"project.xml", rover_project("")}},
                    "scenario.xml"});
  probes.push_back({{{"project.xml", "<project name=\"probe\">" + world + expect + "\n</project>"}}, "project.xml"});

  for (const auto& [files, main] : probes) {
    probe(files, main, false, out);
    probe(files, main, true, out);
  }
  return out;
}

// An entry of a reference page: a table row whose first cell names elements (`x`, `<x>`,
// `x` (in `parent`)), or a generated device section (#### `<x>`).
struct Entry {
  std::set<std::string> elements;
  std::string parent;  // "" for any
  std::string text;
  std::string second_cell;
  // A row of a table whose header's first cell is "element", or a device section: not a row of
  // a table of attributes (a device's `uart` is not the <uart> element).
  bool element_table = false;
};

std::vector<Entry> entries(const std::string& text) {
  std::vector<Entry> out;
  std::stringstream in(text);
  // What applies to every entry under it: a table's header row ("each also takes ..."), and the
  // text between a heading and the first device section under it ("Every element also takes ...").
  std::string header, preamble, previous;
  int section = -1;
  bool in_preamble = false;
  for (std::string line; std::getline(in, line); previous = line) {
    std::smatch m;
    if (std::regex_search(line, m, std::regex(R"(^#### `<(\w+)>`)"))) {
      out.push_back({{m[1]}, "", preamble, "", true});
      section = static_cast<int>(out.size()) - 1;
      in_preamble = false;
      continue;
    }
    if (line.rfind("#", 0) == 0) {
      section = -1;
      preamble.clear();
      in_preamble = true;
    } else if (in_preamble) {
      preamble += line + "\n";
    }
    if (section >= 0) out[static_cast<std::size_t>(section)].text += line + "\n";
    if (line.rfind("|---", 0) == 0 || line.rfind("| ---", 0) == 0) header = previous;
    if (line.rfind("| ", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream row(line.substr(2));
    for (std::string cell; std::getline(row, cell, '|');) cells.push_back(cell);
    if (cells.size() < 2) continue;
    Entry e;
    std::string first = cells[0];
    if (std::regex_search(first, m, std::regex(R"(\(in `<?(\w+)>?`\))"))) {
      e.parent = m[1];
      first = m.prefix();
    }
    for (const auto& n : matches(first, std::regex(R"(`<?(\w+)>?`)"))) e.elements.insert(n);
    if (e.elements.empty()) continue;
    e.text = header + "\n" + line;
    e.second_cell = cells[1];
    e.element_table = std::regex_search(header, std::regex("^\\| [Ee]lement"));
    out.push_back(e);
  }
  return out;
}

// The names an entry documents: `name` spans, and name= in spans and XML.
std::set<std::string> documented(const std::string& text) {
  std::set<std::string> out;
  for (const auto& span : matches(text, std::regex("`([^`]+)`"))) {
    if (std::regex_match(span, std::regex(R"(<?\w+>?)"))) out.insert(std::regex_replace(span, std::regex("[<>]"), ""));
    for (const auto& n : matches(span, std::regex(R"((\w+)=)"))) out.insert(n);
  }
  return out;
}

struct Pages {
  std::map<std::string, std::vector<Entry>> entries;
  std::map<std::string, std::string> text;
};

// The pages an element's reference is on, in order: a URDF robot's mapping in docs/urdf.md
// (which defers to docs/project.md for what is "as in" a robot file), what runs must show in
// docs/expectations.md, the rest in docs/project.md.
std::vector<std::string> pages_for(const Path& path) {
  const bool urdf = path.front() == "urdf_mapping" || std::find(path.begin(), path.end(), kUrdfRobot) != path.end();
  if (path.front() == "scenario" || std::find(path.begin(), path.end(), "expect") != path.end()) return {"expectations.md"};
  if (urdf) return {"urdf.md", "project.md"};
  return {"project.md"};
}

// The text that documents `path`'s element: the rows for it under its parent, or its parent's row
// when that shows it (`<motor t= ...>` in `script`), or its rows for any parent; each page in turn
// while what it found says "as in" another.
std::string reference_of(const Path& path, const Pages& pages, bool* found) {
  const std::string element = bare(path.back());
  const std::string parent = path.size() >= 2 ? bare(path[path.size() - 2]) : "";
  std::string text;
  *found = false;
  for (const std::string& name : pages_for(path)) {
    std::vector<Entry> list;
    for (const Entry& e : pages.entries.at(name))
      if (e.element_table) list.push_back(e);
    std::string here;
    for (const Entry& e : list)
      if (e.elements.count(element) && e.parent == parent && !parent.empty()) here += e.text + "\n";
    if (here.empty())
      for (const Entry& e : list)
        if (e.elements.count(parent) && e.text.find("<" + element + " ") != std::string::npos) here += e.text + "\n";
    if (here.empty())
      for (const Entry& e : list)
        if (e.elements.count(element) && e.parent.empty()) here += e.text + "\n";
    // A scenario's own attributes are told in prose and its example, not in a table.
    if (here.empty() && (element == "scenario" || element == "expect")) here = pages.text.at(name);
    if (!here.empty()) *found = true;
    text += here;
    if (!here.empty() && here.find("as in") == std::string::npos) break;
  }
  return text;
}

Pages load_pages() {
  Pages p;
  for (const char* name : {"project.md", "urdf.md", "expectations.md"}) {
    p.text[name] = page(name);
    p.entries[name] = entries(p.text[name]);
  }
  return p;
}

class DocsProjectFiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { accepted_ = new Accepted(accepted_names()); }
  static void TearDownTestSuite() {
    delete accepted_;
    accepted_ = nullptr;
  }
  static Accepted* accepted_;
};
Accepted* DocsProjectFiles::accepted_ = nullptr;

// Each probe element refused the unknown attribute (with the list of valid ones, when it has any):
// a loader that let one through would leave that element out of the check below, and its users
// without help.
TEST_F(DocsProjectFiles, EveryElementOfTheProbesNamesItsValidAttributes) {
  for (const Path& p : accepted_->probed) {
    std::string where;
    for (const auto& n : p) where += "/" + n;
    EXPECT_TRUE(accepted_->reported.count(p)) << where << " took an unknown attribute without a word";
  }
  EXPECT_GE(accepted_->probed.size(), 60u);
}

TEST_F(DocsProjectFiles, EveryElementAndAttributeTheLoaderAcceptsIsOnItsPage) {
  const Pages pages = load_pages();
  int checked = 0;
  for (const auto& [path, names] : accepted_->attributes) {
    std::string where;
    for (const auto& n : path) where += "/" + n;
    bool found = false;
    const std::string text = reference_of(path, pages, &found);
    EXPECT_TRUE(found) << "<" << path.back() << "> (" << where << ") has no entry in docs/" << pages_for(path).front();
    const std::set<std::string> written = documented(text);
    for (const auto& a : names) {
      ++checked;
      EXPECT_TRUE(written.count(a)) << "<" << path.back() << "> (" << where << ") accepts '" << a << "', which docs/"
                                    << pages_for(path).front() << " does not give it";
    }
  }
  for (const auto& [path, names] : accepted_->children)
    for (const auto& child : names) {
      Path p = path;
      p.push_back(child);
      bool found = false;
      (void)reference_of(p, pages, &found);
      EXPECT_TRUE(found) << "<" << child << "> in <" << path.back() << "> has no entry in docs/" << pages_for(p).front();
    }
  EXPECT_GE(checked, 200);
}

// The reverse, where the pages' form allows it: every element an element table names is one a
// loader accepts; in docs/project.md's rows, whose attributes stand one to a " · "-separated part,
// the first name of each part is an attribute of that element; in docs/urdf.md's mapping table,
// every name in the attributes column (outside parentheses, which hold values) is one.
TEST_F(DocsProjectFiles, EveryElementAndAttributeThePagesNameIsAccepted) {
  std::set<std::string> elements;
  std::map<std::pair<std::string, std::string>, std::set<std::string>> attributes;  // (element, parent)
  for (const auto& [path, names] : accepted_->children)
    for (const auto& n : names) elements.insert(n);
  for (const auto& [path, names] : accepted_->attributes) {
    const std::string parent = path.size() >= 2 ? bare(path[path.size() - 2]) : "";
    elements.insert(bare(path.back()));
    for (const std::string& of : {parent, std::string()}) attributes[{bare(path.back()), of}].insert(names.begin(), names.end());
  }
  const Pages pages = load_pages();
  int checked = 0;
  for (const auto& [name, list] : pages.entries)
    for (const Entry& e : list) {
      if (!e.element_table) continue;
      for (const auto& element : e.elements) {
        EXPECT_TRUE(elements.count(element)) << "docs/" << name << " has a row for <" << element
                                             << ">, an element no loader accepts";
        std::vector<std::string> named;
        if (name == "project.md") {
          std::stringstream parts(std::regex_replace(e.second_cell, std::regex(" · "), "\n"));
          for (std::string part; std::getline(parts, part);) {
            const auto first = matches(part, std::regex("`([^`]+)`"));
            if (!first.empty() && first[0][0] != '<') named.push_back(first[0]);
          }
        } else if (name == "urdf.md") {
          named = matches(std::regex_replace(e.second_cell, std::regex(R"(\([^)]*\))"), ""), std::regex("`([^`<]+)`"));
        }
        const auto& valid = attributes[{element, e.parent}];
        for (const auto& a : named) {
          ++checked;
          EXPECT_TRUE(valid.count(a)) << "docs/" << name << " gives <" << element << "> '" << a
                                      << "', which it does not accept (it accepts: " << join(valid) << ")";
        }
      }
    }
  EXPECT_GE(checked, 90);
}

}  // namespace
}  // namespace sear::test
