// Values a run cannot run are refused when the project is loaded, each at its file and line with
// the accepted range: non-finite and huge numbers (which used to make ODE abort with no summary),
// fractions where a count is due, text that is not UTF-8, names that cannot be file names,
// folders and unusable files where a file is expected. Also: a file with very many errors keeps
// its first hundred and a count, and name checks stay correct (and linear) on 160 000 obstacles.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "project_text.hpp"
#include "scene/diagnostics.hpp"
#include "scene/nearest_name.hpp"
#include "scene/project_loader.hpp"
#include "temp_dir.hpp"

namespace sear {
namespace {

using test::line_of;
using test::replaced;

using sear::test::TempDir;
namespace fs = std::filesystem;

// A valid project with every element whose numbers are tested here; each line is unique, so a
// test can replace one attribute and know the line it is on.
const std::string kBase = R"(<?xml version="1.0"?>
<project name="values">
  <run duration="5" seed="3" trace_rate="50"/>
  <world gravity="0 0 -9.81" step="0.001" solver="iterative" solver_iterations="20">
    <gps_origin latitude="52.2" longitude="0.12" altitude="12"/>
    <magnetic declination_deg="0.9"/>
    <material name="rubber" friction="1.0" bounce="0"/>
    <material name="wood" friction="0.5"/>
    <box name="crate" pos="3 0" size="0.5 0.5 0.4" yaw_deg="20" mass="0" material="wood"/>
    <box name="parcel" pos="-3 0" z="0.5" size="0.3 0.3 0.3" mass="0.8"/>
    <tree name="oak" pos="-3 -3" trunk_radius="0.15" trunk_height="2.5" crown_radius="1.2"/>
    <wall name="north" from="-6 6" to="6 6" height="0.6" thickness="0.15"/>
  </world>
  <robot name="bot" drive="differential">
    <pose x="1" y="2" yaw_deg="0"/>
    <chassis shape="box" size="0.30 0.18 0.06" mass="1.5"/>
    <wheel name="left" pos="0.04 0.11 -0.01" radius="0.045" width="0.025" mass="0.06" material="rubber"/>
    <wheel name="right" pos="0.04 -0.11 -0.01" radius="0.045" width="0.025" mass="0.06" material="rubber"/>
    <caster pos="-0.11 0 -0.035" radius="0.02"/>
    <motor name="left_motor" wheels="left" stall_torque="0.6" no_load_rpm="160" supply_voltage="6" gear_friction="0.02"/>
    <motor name="right_motor" wheels="right" stall_torque="0.6" no_load_speed="16.7"/>
    <script>
      <motor t="0" name="left_motor" duty="0.5" dir="forward"/>
    </script>
  </robot>
</project>
)";


struct Loaded {
  std::string path;
  Diagnostics diagnostics;
  std::optional<ProjectDesc> project;
};

Loaded load(const TempDir& dir, const std::string& xml, const std::string& name = "project.xml") {
  Loaded out;
  out.path = dir.write(name, xml);
  out.project = load_project(out.path, out.diagnostics);
  return out;
}

// Exactly one diagnostic, in `file` at `line`, holding every one of `parts`.
::testing::AssertionResult only_error(const Loaded& l, const std::string& file, int line,
                                      const std::vector<std::string>& parts) {
  if (l.project) return ::testing::AssertionFailure() << "the project loaded";
  if (l.diagnostics.count() != 1 || l.diagnostics.all().size() != 1)
    return ::testing::AssertionFailure() << "expected one error, got:\n" << l.diagnostics.joined();
  const Diagnostic& d = l.diagnostics.all()[0];
  if (fs::path(d.file).lexically_normal() != fs::path(file).lexically_normal() || d.line != line)
    return ::testing::AssertionFailure() << "expected " << file << ":" << line << ", got " << d.str();
  for (const auto& p : parts)
    if (d.message.find(p) == std::string::npos)
      return ::testing::AssertionFailure() << "'" << p << "' is not in: " << d.str();
  return ::testing::AssertionSuccess();
}

TEST(ProjectValues, TheBaseProjectIsValid) {
  TempDir dir;
  const Loaded l = load(dir, kBase);
  EXPECT_TRUE(l.diagnostics.ok()) << l.diagnostics.joined();
  ASSERT_TRUE(l.project.has_value());
  EXPECT_EQ(l.project->world.solver_iterations, 20);
  EXPECT_EQ(l.project->world.solver, WorldDesc::Solver::Iterative);
}

// The direct solver unless the world asks for the iterative one, whose sweeps also take the steps
// the direct one hands over; a solver SEAR does not have is an error on its line.
TEST(ProjectValues, TheSolverIsDirectUnlessTheWorldAsksForTheIterativeOne) {
  TempDir dir;
  const Loaded plain = load(dir, replaced(kBase, R"( solver="iterative" solver_iterations="20")", ""));
  ASSERT_TRUE(plain.project.has_value()) << plain.diagnostics.joined();
  EXPECT_EQ(plain.project->world.solver, WorldDesc::Solver::Direct);
  EXPECT_EQ(plain.project->world.solver_iterations, 20);
  const Loaded direct = load(dir, replaced(kBase, R"(solver="iterative" solver_iterations="20")",
                                           R"(solver="direct" solver_iterations="50")"));
  ASSERT_TRUE(direct.project.has_value()) << direct.diagnostics.joined();
  EXPECT_EQ(direct.project->world.solver, WorldDesc::Solver::Direct);
  EXPECT_EQ(direct.project->world.solver_iterations, 50);
  EXPECT_TRUE(only_error(load(dir, replaced(kBase, R"(solver="iterative")", R"(solver="quick")")),
                         dir.path() / "project.xml", 4,
                         {"<world> attribute 'solver': 'quick' is not one of direct, iterative"}));
}

// One attribute changed to a value that is out of its range; the error names the line and range.
struct OutOfRange {
  std::string from, to;
  std::vector<std::string> parts;
};

TEST(ProjectValues, ValuesThatMadeOdeAbortAreRefusedWithTheirRange) {
  // Each of these ran until ODE's "assertion !bSafeNormalize4Fault failed" aborted `sear run`
  // with no summary (tried on the default project): they must now stop at loading.
  const std::vector<OutOfRange> cases = {
      {R"(gravity="0 0 -9.81")", R"(gravity="0 0 -1e300")", {"'gravity': -1e300 is out of range", "-100..100 m/s^2"}},
      {R"(mass="1.5")", R"(mass="0.0001")", {"<chassis> attribute 'mass': 0.0001 kg", "0.01..100000 kg"}},
      {R"(crown_radius="1.2")", R"(crown_radius="1e200")", {"'crown_radius': 1e200 m", "0..100 m"}},
      {R"(height="0.6")", R"(height="1e200")", {"<wall> attribute 'height'", "0.001..1000 m"}},
      {R"(<wheel name="left" pos="0.04 0.11 -0.01" radius="0.045" width="0.025" mass="0.06")",
       R"(<wheel name="left" pos="0.04 0.11 -0.01" radius="0.045" width="0.025" mass="1e6")",
       {"<wheel> attribute 'mass': 1e6 kg", "0.001..10000 kg"}},
      {R"(stall_torque="0.6" no_load_rpm="160")", R"(stall_torque="1e7" no_load_rpm="160")",
       {"'stall_torque': 1e7 N*m", "> 0 and <= 1e6 N*m"}},
      {R"(no_load_rpm="160")", R"(no_load_rpm="0")", {"'no_load_rpm': 0 rpm", "> 0 and <= 1e6 rpm"}},
  };
  for (const auto& c : cases) {
    TempDir dir;
    const std::string xml = replaced(kBase, c.from, c.to);
    EXPECT_TRUE(only_error(load(dir, xml), dir.path() / "project.xml", line_of(xml, c.to), c.parts)) << c.to;
  }
}

TEST(ProjectValues, EveryNumberHasARange) {
  const std::vector<OutOfRange> cases = {
      {R"(step="0.001")", R"(step="0.1")", {"'step': 0.1 s", "between 0.00001 and 0.01 s"}},
      {R"(solver_iterations="20")", R"(solver_iterations="0")", {"'solver_iterations'", "1..1000"}},
      {R"(altitude="12")", R"(altitude="1e300")", {"'altitude'", "-11000..100000 m"}},
      {R"(name="rubber" friction="1.0")", R"(name="rubber" friction="1e300")", {"'friction'", "0..10"}},
      {R"(bounce="0")", R"(bounce="2")", {"'bounce'", "0..1"}},
      {R"(size="0.5 0.5 0.4")", R"(size="0.5 0.5 1e200")", {"<box> attribute 'size'", "0.001..1000 m"}},
      {R"(pos="3 0")", R"(pos="3e6 0")", {"<box> attribute 'pos'", "-100000..100000 m"}},
      {R"(z="0.5")", R"(z="-1e5")", {"<box> attribute 'z'", "-10000..10000 m"}},
      {R"(yaw_deg="20")", R"(yaw_deg="1e300")", {"<box> attribute 'yaw_deg'", "-360..360 degrees"}},
      {R"(mass="0.8")", R"(mass="-0.8")", {"<box> attribute 'mass'", "0..1e6 kg"}},
      {R"(trunk_radius="0.15")", R"(trunk_radius="1e200")", {"'trunk_radius'", "0.001..1000 m"}},
      {R"(trunk_height="2.5")", R"(trunk_height="1000")", {"'trunk_height'", "0.01..200 m"}},
      {R"(from="-6 6")", R"(from="-6e300 6")", {"<wall> attribute 'from'", "-100000..100000 m"}},
      {R"(<pose x="1")", R"(<pose x="1e9")", {"<pose> attribute 'x'", "-100000..100000 m"}},
      {R"(size="0.30 0.18 0.06")", R"(size="0.30 0.18 1000")", {"<chassis> attribute 'size'", "0.001..100 m"}},
      {R"(<caster pos="-0.11 0 -0.035")", R"(<caster pos="-0.11 0 -1e300")", {"<caster> attribute 'pos'", "-100..100 m"}},
      {R"(supply_voltage="6")", R"(supply_voltage="1e9")", {"'supply_voltage'", "0.1..1000 V"}},
      {R"(no_load_speed="16.7")", R"(no_load_speed="1e300")", {"'no_load_speed'", "> 0 and <= 1e5 rad/s"}},
      {R"(duty="0.5")", R"(duty="1.5")", {"'duty'", "0..1"}},
      {R"(seed="3")", R"(seed="5e9")", {"'seed'", "0..4294967295"}},
  };
  for (const auto& c : cases) {
    TempDir dir;
    const std::string xml = replaced(kBase, c.from, c.to);
    EXPECT_TRUE(only_error(load(dir, xml), dir.path() / "project.xml", line_of(xml, c.to), c.parts)) << c.to;
  }
}

TEST(ProjectValues, TheBoundsThemselvesAreAccepted) {
  // The other side of each bound above: a constant moved inwards fails here.
  TempDir dir;
  std::string xml = replaced(kBase, R"(gravity="0 0 -9.81")", R"(gravity="100 -100 -100")");
  xml = replaced(xml, R"(step="0.001")", R"(step="0.01")");
  xml = replaced(xml, R"(mass="1.5")", R"(mass="0.01")");
  xml = replaced(xml, R"(crown_radius="1.2")", R"(crown_radius="100")");
  xml = replaced(xml, R"(height="0.6")", R"(height="1000")");
  xml = replaced(xml, R"(stall_torque="0.6" no_load_rpm="160")", R"(stall_torque="1e6" no_load_rpm="1e6")");
  xml = replaced(xml, R"(name="rubber" friction="1.0")", R"(name="rubber" friction="10")");
  xml = replaced(xml, R"(altitude="12")", R"(altitude="-11000")");
  xml = replaced(xml, R"(seed="3")", R"(seed="4294967295")");
  xml = replaced(xml, R"(<pose x="1")", R"(<pose x="-100000")");
  xml = replaced(xml, R"(size="0.5 0.5 0.4")", R"(size="0.001 1000 0.4")");
  const Loaded l = load(dir, xml);
  EXPECT_TRUE(l.diagnostics.ok()) << l.diagnostics.joined();
  ASSERT_TRUE(l.project.has_value());
  EXPECT_EQ(l.project->run.seed, 4294967295u);
  EXPECT_DOUBLE_EQ(l.project->robots[0].chassis.mass_kg, 0.01);
  EXPECT_DOUBLE_EQ(l.project->world.gravity.x(), 100.0);
}

TEST(ProjectValues, NanAndInfinityAreNotNumbers) {
  for (const char* bad : {"nan", "NAN", "inf", "-inf", "infinity", "1e400", "-1e400"}) {
    for (const std::string& from : {std::string(R"(step="0.001")"), std::string(R"(mass="1.5")"),
                                    std::string(R"(t="0")"), std::string(R"(pos="3 0")")}) {
      TempDir dir;
      const std::string attribute = from.substr(0, from.find('='));
      const std::string to = from == R"(pos="3 0")" ? "pos=\"3 " + std::string(bad) + "\""
                                                    : attribute + "=\"" + bad + "\"";
      const std::string xml = replaced(kBase, from, to);
      EXPECT_TRUE(only_error(load(dir, xml), dir.path() / "project.xml", line_of(xml, to),
                             {"attribute '" + attribute + "': expected a number", std::string("got '") + bad + "'"}))
          << to;
    }
  }
}

TEST(ProjectValues, CountsMustBeWholeNumbers) {
  TempDir dir;
  std::string xml = replaced(kBase, R"(solver_iterations="20")", R"(solver_iterations="2.5")");
  EXPECT_TRUE(only_error(load(dir, xml), dir.path() / "project.xml", 4,
                         {"'solver_iterations': expected a whole number in 1..1000, got '2.5'"}));
  xml = replaced(kBase, R"(seed="3")", R"(seed="3.7")");
  EXPECT_TRUE(only_error(load(dir, xml), dir.path() / "project.xml", 3,
                         {"'seed': expected a whole number in 0..4294967295, got '3.7'"}));
}

TEST(ProjectValues, ABeamNeedingTooManyRaysIsRefused) {
  TempDir dir;
  dir.write("fw", "");
  fs::permissions(dir.path() / "fw", fs::perms::owner_all);
  const std::string mcu = R"(    <mcu name="main">
      <firmware executable="fw"/>
      <gp2d12 name="ir" adc="0" half_angle_deg="2" resolution_deg="0.01"/>
      <gp2d12 name="ok" adc="1" half_angle_deg="45" resolution_deg="1"/>
    </mcu>
  </robot>)";
  const std::string xml = replaced(kBase, "  </robot>", mcu);
  // 2 degrees at 0.01 degree steps is some 125 000 rays per measurement; the run casts at most 100 000.
  EXPECT_TRUE(only_error(load(dir, xml), dir.path() / "project.xml", line_of(xml, R"(name="ir")"),
                         {"half_angle_deg 2 with resolution_deg 0.01 needs", "rays per measurement; at most 100000"}));
}

TEST(ProjectValues, AFileThatIsNotUtf8IsRefusedAtItsLine) {
  TempDir dir;
  // "Müller" in Latin-1: the u-umlaut is the single byte 0xFC.
  const std::string xml = replaced(kBase, R"(<box name="crate")", "<box name=\"M\xFCller\"");
  const int line = line_of(xml, "<box name=\"M");
  EXPECT_TRUE(only_error(load(dir, xml), dir.path() / "project.xml", line,
                         {"not valid UTF-8 (byte 0xFC at column 17)", "save it as UTF-8"}));
  // The same name in UTF-8 is valid text, but not a file name SEAR accepts: refused as a name.
  const std::string utf8 = replaced(kBase, R"(<box name="crate")", "<box name=\"M\xC3\xBCller\"");
  EXPECT_TRUE(only_error(load(dir, utf8), dir.path() / "project.xml", line,
                         {"<box> name 'M\xC3\xBCller': use letters, digits, '_' and '-' only"}));
  // A project's name is free text and may be any printable UTF-8.
  const Loaded ok = load(dir, replaced(kBase, R"(<project name="values">)", "<project name=\"M\xC3\xBCller's rover\">"));
  ASSERT_TRUE(ok.project.has_value()) << ok.diagnostics.joined();
  EXPECT_EQ(ok.project->name, "M\xC3\xBCller's rover");
}

TEST(ProjectValues, ARobotFileThatIsNotUtf8NamesThatFile) {
  TempDir dir;
  const std::string robot = dir.write("bot.xml", "<robot name=\"bot\">\n  <!-- d\xE9j\xE0 vu -->\n</robot>\n");
  const std::string xml = "<project>\n  <world/>\n  <robot file=\"bot.xml\"/>\n</project>\n";
  EXPECT_TRUE(only_error(load(dir, xml), robot, 2, {"not valid UTF-8 (byte 0xE9 at column 9)"}));
}

TEST(ProjectValues, CharacterReferencesCannotSmuggleControlCharacters) {
  TempDir dir;
  const std::string xml = replaced(kBase, R"(<project name="values">)", R"(<project name="a&#x1;b">)");
  EXPECT_TRUE(only_error(load(dir, xml), dir.path() / "project.xml", 2,
                         {"<project> attribute 'name' holds a control character (byte 2 is 0x01)"}));
  // A lone surrogate is no character: tinyxml2 writes it as bytes that are not UTF-8.
  const std::string surrogate = replaced(kBase, R"(<project name="values">)", R"(<project name="a&#xD800;">)");
  const Loaded l = load(dir, surrogate);
  EXPECT_FALSE(l.project.has_value());
  const std::string material =
      replaced(kBase, R"(<material name="wood" friction="0.5"/>)",
               "<material name=\"wood\" friction=\"0.5\"/>\n    <material name=\"wo&#x9b;od\"/>");
  const std::string file = dir.path() / "project.xml";
  EXPECT_TRUE(only_error(load(dir, material), file, line_of(material, "<material name=\"wo&"),
                         {"<material> attribute 'name' holds a control character (byte 3 is 0x9B)"}));
}

TEST(ProjectValues, ANonUtf8ProjectFileNameIsRefused) {
  TempDir dir;
  const Loaded l = load(dir, kBase, "caf\xE9.xml");
  ASSERT_EQ(l.diagnostics.count(), 1u) << l.diagnostics.joined();
  EXPECT_EQ(l.diagnostics.all()[0].line, 0);
  EXPECT_NE(l.diagnostics.all()[0].message.find("file's name is not valid UTF-8"), std::string::npos);
}

TEST(ProjectValues, NamesMustBeFileNameParts) {
  TempDir dir;
  const std::string file = dir.path() / "project.xml";
  const int line = line_of(kBase, R"(<box name="crate")");
  for (const char* bad : {"a/b", ".hidden", "..", "a b", "tab\t"}) {
    const std::string xml = replaced(kBase, R"(<box name="crate")", std::string("<box name=\"") + bad + "\"");
    EXPECT_TRUE(only_error(load(dir, xml), file, line, {"use letters, digits, '_' and '-' only"})) << bad;
  }
  const std::string longest(64, 'x');
  EXPECT_TRUE(load(dir, replaced(kBase, R"(<box name="crate")", "<box name=\"" + longest + "\"")).diagnostics.ok());
  const std::string xml = replaced(kBase, R"(<box name="crate")", "<box name=\"" + longest + "y\"");
  EXPECT_TRUE(only_error(load(dir, xml), file, line, {"is 65 characters long; names become file names: at most 64"}));
}

TEST(ProjectValues, FoldersAndUnusableFilesWhereAFileIsExpected) {
  TempDir dir;
  fs::create_directories(dir.path() / "folder.obj");
  fs::create_directories(dir.path() / "folder.png");
  fs::create_directories(dir.path() / "folder.xml");
  const std::string file = dir.path() / "project.xml";
  const auto world_with = [&](const std::string& element) {
    return replaced(kBase, "  </world>", element + "\n  </world>");
  };
  std::string xml = world_with(R"(    <mesh name="rock" file="folder.obj"/>)");
  EXPECT_TRUE(only_error(load(dir, xml), file, line_of(xml, "<mesh"),
                         {"<mesh> mesh file 'folder.obj' is a folder, expected a file"}));
  xml = world_with(R"(    <terrain type="heightmap" image="folder.png" size="10 10"/>)");
  EXPECT_TRUE(only_error(load(dir, xml), file, line_of(xml, "<terrain"),
                         {"<terrain> image 'folder.png' is a folder, expected a file"}));
  xml = "<project>\n  <world/>\n  <robot file=\"folder.xml\"/>\n</project>\n";
  EXPECT_TRUE(only_error(load(dir, xml), file, 3, {"<robot> robot file 'folder.xml' is a folder, expected a file"}));
  // A mesh whose vertex is beyond a float (1e39) would reach ODE as infinity.
  dir.write("huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n");
  xml = world_with(R"(    <mesh name="huge" file="huge.obj"/>)");
  EXPECT_TRUE(only_error(load(dir, xml), file, line_of(xml, "<mesh"),
                         {"mesh file 'huge.obj': vertex 3", "finite and within -100000..100000 m"}));
}

std::string with_mcu(const std::string& firmware, const std::string& extra = "") {
  return replaced(kBase, "  </robot>", "    <mcu name=\"main\">\n      " + firmware + "\n" + extra + "    </mcu>\n  </robot>");
}

TEST(ProjectValues, FirmwareMustBeAnExecutableOrCSources) {
  TempDir dir;
  const std::string file = dir.path() / "project.xml";
  dir.write("plain", "not a program");
  fs::permissions(dir.path() / "plain", fs::perms::owner_read | fs::perms::owner_write);
  dir.write("runnable", "#!/bin/sh\n");
  fs::permissions(dir.path() / "runnable", fs::perms::owner_all);
  fs::create_directories(dir.path() / "src");
  dir.write("main.c", "int main(void) { return 0; }\n");
  dir.write("main.h", "\n");
  const int line = line_of(with_mcu(""), "<mcu") + 1;

  EXPECT_TRUE(load(dir, with_mcu(R"(<firmware executable="runnable"/>)")).diagnostics.ok());
  EXPECT_TRUE(load(dir, with_mcu(R"(<firmware sources="main.c"/>)")).diagnostics.ok());
  EXPECT_TRUE(only_error(load(dir, with_mcu(R"(<firmware executable="plain"/>)")), file, line,
                         {"firmware executable 'plain' is not executable", "chmod +x"}));
  EXPECT_TRUE(only_error(load(dir, with_mcu(R"(<firmware executable="src"/>)")), file, line,
                         {"firmware executable 'src' is a folder, expected a file"}));
  EXPECT_TRUE(only_error(load(dir, with_mcu(R"(<firmware sources="src"/>)")), file, line,
                         {"firmware source 'src' is a folder, expected a file"}));
  EXPECT_TRUE(only_error(load(dir, with_mcu(R"(<firmware sources="main.h"/>)")), file, line,
                         {"firmware source 'main.h' is not a C or C++ source (.c, .cpp, .cc, .cxx); headers are found through #include"}));
  EXPECT_TRUE(only_error(load(dir, with_mcu(R"(<firmware sources=" "/>)")), file, line,
                         {"'sources' names no files"}));
  EXPECT_TRUE(only_error(load(dir, with_mcu(R"(<firmware sources="main.c"/>)", "      <uart port=\"1\" receive=\"src\"/>\n")),
                         file, line + 1, {"UART capture 'src' is a folder, expected a file"}));
}

TEST(ProjectValues, ConsoleUartIsAPortOrMinusOneForNone) {
  TempDir dir;
  dir.write("runnable", "#!/bin/sh\n");
  fs::permissions(dir.path() / "runnable", fs::perms::owner_all);
  const auto mcu = [](const std::string& console) {
    return replaced(kBase, "  </robot>",
                    "    <mcu name=\"main\" console_uart=\"" + console +
                        "\">\n      <firmware executable=\"runnable\"/>\n    </mcu>\n  </robot>");
  };
  const Loaded none = load(dir, mcu("-1"));
  ASSERT_TRUE(none.project.has_value()) << none.diagnostics.joined();
  EXPECT_EQ(none.project->robots[0].mcus[0].console_uart, -1);
  const std::string file = dir.path() / "project.xml";
  const int line = line_of(mcu("4"), "<mcu");
  EXPECT_TRUE(only_error(load(dir, mcu("4")), file, line, {"'console_uart': 4 is out of range (expected 0..3, or -1 for no console)"}));
  EXPECT_TRUE(only_error(load(dir, mcu("1.5")), file, line, {"'console_uart': expected a whole number in 0..3"}));
  EXPECT_TRUE(only_error(load(dir, mcu("nan")), file, line, {"'console_uart': expected a number, got 'nan'"}));
}

TEST(ProjectValues, AMeshChassisNeedsAVolume) {
  // Its bounding box gives the chassis' inertia: a flat mesh would give ODE a zero inertia.
  TempDir dir;
  dir.write("flat.obj", "v 0 0 0\nv 0.3 0 0\nv 0 0.2 0\nf 1 2 3\n");
  dir.write("solid.obj", "v 0 0 0\nv 0.3 0 0\nv 0 0.2 0\nv 0 0 0.05\nf 1 2 3\nf 1 2 4\n");
  const auto chassis = [](const std::string& mesh) {
    return replaced(kBase, R"(<chassis shape="box" size="0.30 0.18 0.06" mass="1.5"/>)",
                    "<chassis shape=\"mesh\" file=\"" + mesh + "\" mass=\"1.5\"/>");
  };
  EXPECT_TRUE(load(dir, chassis("solid.obj")).diagnostics.ok());
  const std::string xml = chassis("flat.obj");
  EXPECT_TRUE(only_error(load(dir, xml), dir.path() / "project.xml", line_of(xml, "<chassis"),
                         {"<chassis> mesh is 0.3 x 0.2 x 0 m once scaled; each side must be in 0.001..100 m"}));
}

TEST(Diagnostics, KeepsTheFirstHundredAndCountsTheRest) {
  Diagnostics d;
  for (int i = 1; i <= 1000; ++i) d.error("f.xml", i, "bad");
  EXPECT_FALSE(d.ok());
  EXPECT_EQ(d.count(), 1000u);
  ASSERT_EQ(d.all().size(), 100u);
  EXPECT_EQ(d.all().back().line, 100);
  const std::string text = d.joined();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 101);
  EXPECT_NE(text.find("f.xml:100: error: bad\n... and 900 more errors\n"), std::string::npos);
  Diagnostics one;
  for (int i = 1; i <= 101; ++i) one.error("f.xml", i, "bad");
  EXPECT_NE(one.joined().find("... and 1 more error\n"), std::string::npos);
}

TEST(ProjectValues, AFileWithVeryManyErrorsKeepsAHundred) {
  TempDir dir;
  std::string xml = "<project>\n  <world>\n";
  constexpr int kBad = 300000;
  for (int i = 0; i < kBad; ++i) xml += "    <boxx/>\n";
  xml += "  </world>\n</project>\n";
  const Loaded l = load(dir, xml);
  EXPECT_EQ(l.diagnostics.count(), static_cast<std::size_t>(kBad));
  ASSERT_EQ(l.diagnostics.all().size(), Diagnostics::kMaxKept);
  EXPECT_EQ(l.diagnostics.all()[0].line, 3);
  EXPECT_EQ(l.diagnostics.all()[0].message, "unknown element <boxx> in <world> (did you mean 'box'?); valid: <gps_origin>, <magnetic>, "
            "<material>, <terrain>, <box>, <tree>, <wall>, <mesh>");
  EXPECT_NE(l.diagnostics.joined().find("... and 299900 more errors"), std::string::npos);
}

TEST(ProjectValues, DuplicateNamesAmong160000BoxesAreAllFound) {
  // A generated world: name checks must stay linear (see docs/project.md for the time).
  TempDir dir;
  constexpr int kBoxes = 160000;
  std::string xml = "<project>\n  <world>\n";
  std::vector<int> duplicate_lines;
  for (int i = 0; i < kBoxes; ++i) {
    // Three boxes reuse the name of an earlier one.
    const int name = (i == 1000 || i == 90000 || i == 159999) ? i - 777 : i;
    if (name != i) duplicate_lines.push_back(3 + i);
    xml += "    <box name=\"b" + std::to_string(name) + "\" pos=\"" + std::to_string(i % 400) + " " +
           std::to_string(i / 400) + "\" size=\"0.5 0.5 0.5\"/>\n";
  }
  xml += "  </world>\n</project>\n";
  const Loaded l = load(dir, xml);
  ASSERT_EQ(l.diagnostics.count(), 3u) << l.diagnostics.joined();
  for (std::size_t k = 0; k < 3; ++k) {
    const int i = duplicate_lines[k] - 3;
    EXPECT_EQ(l.diagnostics.all()[k].line, duplicate_lines[k]);
    EXPECT_EQ(l.diagnostics.all()[k].message,
              "box name 'b" + std::to_string(i - 777) + "' is already used by another obstacle or robot (line " +
                  std::to_string(3 + i - 777) + ")");
  }
}

TEST(ProjectValues, ManyUnknownMaterialsStillGetSuggestionsAndFinish) {
  // Suggestions are worked out only while errors are kept: 20 000 misspellings against 20 000
  // materials would otherwise be 4e8 edit distances.
  TempDir dir;
  constexpr int kCount = 20000;
  std::string xml = "<project>\n  <world>\n";
  for (int i = 0; i < kCount; ++i) xml += "    <material name=\"mat" + std::to_string(i) + "\"/>\n";
  for (int i = 0; i < kCount; ++i)
    xml += "    <box name=\"b" + std::to_string(i) + "\" material=\"mta" + std::to_string(i) + "\"/>\n";
  xml += "  </world>\n</project>\n";
  const Loaded l = load(dir, xml);
  EXPECT_EQ(l.diagnostics.count(), static_cast<std::size_t>(kCount));
  ASSERT_FALSE(l.diagnostics.all().empty());
  EXPECT_EQ(l.diagnostics.all()[0].line, 3 + kCount);
  EXPECT_NE(l.diagnostics.all()[0].message.find("uses unknown material 'mta0' (did you mean 'mat0'?)"),
            std::string::npos)
      << l.diagnostics.all()[0].message;
}

TEST(NearestName, SkipsCandidatesWhoseLengthRulesThemOut) {
  EXPECT_EQ(nearest_name("radus", {"radius", "r", "a_very_long_attribute_name"}), "radius");
  EXPECT_EQ(nearest_name(std::string(100000, 'x'), {"radius"}), "");
  Diagnostics full;
  for (std::size_t i = 0; i < Diagnostics::kMaxKept; ++i) full.error("f", 1, "e");
  EXPECT_EQ(did_you_mean(full, "radus", {"radius"}), "");
  EXPECT_EQ(did_you_mean(Diagnostics(), "radus", {"radius"}), " (did you mean 'radius'?)");
}

}  // namespace
}  // namespace sear
