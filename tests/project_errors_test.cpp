// Every kind of bad input in a project (or a robot file it includes) gets a diagnostic naming the
// file, the line and what was expected; a project with several independent mistakes reports all
// of them. Each test writes its files to a fresh folder of its own under the system temp folder.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "project_text.hpp"
#include "temp_dir.hpp"
#include "scene/diagnostics.hpp"
#include "scene/geodetic.hpp"
#include "scene/device_kind.hpp"
#include "scene/project_loader.hpp"

namespace sear {
namespace {

using test::line_of;
using test::replaced;

using sear::test::TempDir;

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;



bool same_file(const std::string& a, const std::string& b) {
  return fs::path(a).lexically_normal() == fs::path(b).lexically_normal();
}

// The first diagnostic whose message holds every one of `parts`, or nullptr.
const Diagnostic* find(const Diagnostics& diagnostics, const std::vector<std::string>& parts) {
  for (const auto& d : diagnostics.all()) {
    if (std::all_of(parts.begin(), parts.end(),
                    [&](const std::string& p) { return d.message.find(p) != std::string::npos; }))
      return &d;
  }
  return nullptr;
}

// A diagnostic exists in `file` at `line` whose message holds every one of `parts`.
::testing::AssertionResult reports(const Diagnostics& diagnostics, const std::string& file, int line,
                                   const std::vector<std::string>& parts) {
  const Diagnostic* d = find(diagnostics, parts);
  std::string wanted;
  for (const auto& p : parts) wanted += " [" + p + "]";
  if (!d) return ::testing::AssertionFailure() << "no diagnostic holds" << wanted << "; got:\n" << diagnostics.joined();
  if (!same_file(d->file, file))
    return ::testing::AssertionFailure() << "diagnostic" << wanted << " names file '" << d->file << "', expected '"
                                         << file << "'; got:\n" << diagnostics.joined();
  if (d->line != line)
    return ::testing::AssertionFailure() << "diagnostic" << wanted << " is on line " << d->line << ", expected "
                                         << line << "; got:\n" << diagnostics.joined();
  return ::testing::AssertionSuccess();
}

// A valid project with an inline differential-drive robot; tests break one thing in it at a time.
const std::string kGoodProject = R"(<?xml version="1.0"?>
<project name="errors">
  <run duration="5" seed="3" trace_rate="50"/>
  <world gravity="0 0 -9.81" step="0.001">
    <material name="rubber" friction="1.0"/>
    <material name="plastic" friction="0.4"/>
    <material name="wood" friction="0.5"/>
    <box name="crate" pos="3 0" size="0.5 0.5 0.4" material="wood"/>
  </world>
  <robot name="bot" drive="differential">
    <pose x="1" y="2" yaw_deg="0"/>
    <chassis shape="box" size="0.30 0.18 0.06" mass="1.5" material="plastic"/>
    <wheel name="left" pos="0.04 0.11 -0.01" radius="0.045" width="0.025" mass="0.06" material="rubber"/>
    <wheel name="right" pos="0.04 -0.11 -0.01" radius="0.045" width="0.025" mass="0.06" material="rubber"/>
    <caster pos="-0.11 0 -0.035" radius="0.02"/>
    <motor name="left_motor" wheels="left" stall_torque="0.6" no_load_rpm="160"/>
    <motor name="right_motor" wheels="right" stall_torque="0.6" no_load_rpm="160"/>
    <script>
      <motor t="0" name="left_motor" duty="0.5" dir="forward"/>
      <motor t="0" name="right_motor" duty="0.5" dir="forward"/>
    </script>
  </robot>
</project>
)";

const std::string kLeftWheel = R"(<wheel name="left" pos="0.04 0.11 -0.01" radius="0.045")";
const std::string kChassis = R"(<chassis shape="box" size="0.30 0.18 0.06" mass="1.5" material="plastic"/>)";
const std::string kWorldEnd = "  </world>\n";

// The world used by projects that include a robot file: the materials the bundled robots use.
const std::string kWorldForRobotFiles = R"(  <world step="0.001">
    <material name="rubber" friction="1.0"/>
    <material name="plastic" friction="0.4"/>
  </world>
)";

// A project that includes `robot_file` from its own folder, with the bundled robots' materials.
std::string project_including(const std::string& robot_file) {
  return "<?xml version=\"1.0\"?>\n<project name=\"including\">\n" + kWorldForRobotFiles + "  <robot file=\"" +
         robot_file + "\">\n    <pose x=\"0\" y=\"0\"/>\n  </robot>\n</project>\n";
}

struct Loaded {
  std::string path;
  Diagnostics diagnostics;
  std::optional<ProjectDesc> project;
};

// Writes `xml` as project.xml in `dir` and loads it.
Loaded load(const TempDir& dir, const std::string& xml) {
  Loaded out;
  out.path = dir.write("project.xml", xml);
  out.project = load_project(out.path, out.diagnostics);
  return out;
}

TEST(ProjectErrors, TheBaseProjectOfTheseTestsIsValid) {
  TempDir dir;
  const Loaded l = load(dir, kGoodProject);
  EXPECT_TRUE(l.diagnostics.ok()) << l.diagnostics.joined();
  ASSERT_TRUE(l.project.has_value());
  ASSERT_EQ(l.project->robots.size(), 1u);
  EXPECT_EQ(l.project->robots[0].wheels.size(), 2u);
  EXPECT_EQ(l.project->robots[0].script.size(), 2u);
}

TEST(ProjectErrors, MalformedXmlNamesTheLineOfTheUnclosedTag) {
  TempDir dir;
  const std::string xml = R"(<?xml version="1.0"?>
<project name="broken">
  <run duration="5">
  <world step="0.001"/>
</project>
)";
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  ASSERT_EQ(l.diagnostics.all().size(), 1u) << l.diagnostics.joined();
  // </project> comes while <run> (line 3) is still open: said where <run> is, in our words.
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<run"),
                      {"malformed XML: <run> is never closed: </project> on line 5 comes before its </run>"}));
}

TEST(ProjectErrors, WrongRootElement) {
  TempDir dir;
  const std::string xml = R"(<?xml version="1.0"?>

<robot name="not_a_project" drive="differential">
</robot>
)";
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  ASSERT_EQ(l.diagnostics.all().size(), 1u) << l.diagnostics.joined();
  EXPECT_TRUE(reports(l.diagnostics, l.path, 3, {"<project>", "root element"}));
}

TEST(ProjectErrors, UnknownElementSuggestsTheNearestName) {
  TempDir dir;
  std::string xml = replaced(kGoodProject, R"(<box name="crate")", R"(<boxx name="crate")");
  xml = replaced(xml, "<caster ", "<castor ");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<boxx"),
                      {"unknown element <boxx> in <world>", "did you mean 'box'"}));
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<castor"),
                      {"unknown element <castor> in <robot>", "did you mean 'caster'"}));
}

TEST(ProjectErrors, UnknownAttributeSuggestsTheNearestName) {
  TempDir dir;
  const std::string xml =
      replaced(kGoodProject, kLeftWheel, R"(<wheel name="left" pos="0.04 0.11 -0.01" radus="0.045")");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  const int line = line_of(xml, "radus=");
  EXPECT_TRUE(reports(l.diagnostics, l.path, line, {"unknown attribute 'radus' on <wheel>", "did you mean 'radius'"}));
  // With the misspelling, the wheel also lacks its radius: said on the same line.
  EXPECT_TRUE(reports(l.diagnostics, l.path, line, {"<wheel> needs attribute 'radius'"}));
}

// Issue 22: a name too far from every valid one for a suggestion still shows what the element
// takes, in the order the format lists it, each name once.
TEST(ProjectErrors, UnknownAttributeListsTheValidOnes) {
  TempDir dir;
  const std::string xml =
      replaced(kGoodProject, kLeftWheel, R"(<wheel name="left" pos="0.04 0.11 -0.01" diameter="0.09")");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "diameter="),
                      {"unknown attribute 'diameter' on <wheel>; valid: name, pos, radius, width, mass, steered, "
                       "material"}));
}

TEST(ProjectErrors, ANumberThatIsNotANumber) {
  TempDir dir;
  std::string xml = replaced(kGoodProject, kChassis,
                             R"(<chassis shape="box" size="0.30 0.18 0.06" mass="abc" material="plastic"/>)");
  xml = replaced(xml, kLeftWheel, R"(<wheel name="left" pos="0.04 zero -0.01" radius="0.045")");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<chassis"),
                      {"<chassis> attribute 'mass'", "expected a number", "got 'abc'"}));
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, R"(<wheel name="left")"),
                      {"<wheel> attribute 'pos'", "expected a number", "got 'zero'"}));
  EXPECT_EQ(l.diagnostics.all().size(), 2u) << l.diagnostics.joined();
}

TEST(ProjectErrors, NegativeChassisMass) {
  TempDir dir;
  const std::string xml = replaced(kGoodProject, kChassis,
                                   R"(<chassis shape="box" size="0.30 0.18 0.06" mass="-1.5" material="plastic"/>)");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  ASSERT_EQ(l.diagnostics.all().size(), 1u) << l.diagnostics.joined();
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<chassis"),
                      {"<chassis> attribute 'mass'", "-1.5", "out of range", "expected 0.01..100000 kg"}));
}

TEST(ProjectErrors, ZeroWheelRadius) {
  TempDir dir;
  const std::string xml =
      replaced(kGoodProject, kLeftWheel, R"(<wheel name="left" pos="0.04 0.11 -0.01" radius="0")");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  ASSERT_EQ(l.diagnostics.all().size(), 1u) << l.diagnostics.joined();
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, R"(<wheel name="left")"),
                      {"<wheel> attribute 'radius'", "out of range", "expected 0.001..10 m"}));
}

TEST(ProjectErrors, MissingMeshFileNamesTheElementAndThePath) {
  TempDir dir;
  std::string xml = replaced(kGoodProject, kWorldEnd,
                             "    <mesh name=\"rock\" file=\"meshes/missing_rock.obj\" pos=\"2 3\"/>\n" + kWorldEnd);
  xml = replaced(xml, kChassis, R"(<chassis shape="mesh" file="no_chassis.stl" mass="1.5" material="plastic"/>)");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  ASSERT_EQ(l.diagnostics.all().size(), 2u) << l.diagnostics.joined();
  const std::string rock_path = (dir.path() / "meshes" / "missing_rock.obj").lexically_normal().string();
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<mesh name=\"rock\""),
                      {"<mesh>", "'meshes/missing_rock.obj'", "not found", rock_path}));
  const std::string chassis_path = (dir.path() / "no_chassis.stl").lexically_normal().string();
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<chassis"),
                      {"<chassis>", "'no_chassis.stl'", "not found", chassis_path}));
}

TEST(ProjectErrors, MeshFileAssimpCannotLoad) {
  TempDir dir;
  const std::string broken = std::string(SEAR_TEST_DATA) + "/meshes/broken.obj";
  const std::string xml = replaced(kGoodProject, kWorldEnd,
                                   "    <mesh name=\"junk\" file=\"" + broken + "\" pos=\"2 3\"/>\n" + kWorldEnd);
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  ASSERT_EQ(l.diagnostics.all().size(), 1u) << l.diagnostics.joined();
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<mesh name=\"junk\""), {"<mesh> mesh file", "broken.obj"}));
  // Something follows the file name: the reason assimp gave.
  const std::string& message = l.diagnostics.all()[0].message;
  const auto after = message.find("broken.obj'");
  ASSERT_NE(after, std::string::npos) << message;
  EXPECT_GT(message.size(), after + std::string("broken.obj': ").size()) << message;
}

const std::string kHeightmapTerrain =
    R"(    <terrain type="heightmap" image="IMAGE" size="10 10" min_height="0" max_height="1"/>
)";

TEST(ProjectErrors, MissingHeightmapImage) {
  TempDir dir;
  const std::string xml = replaced(
      kGoodProject, kWorldEnd, replaced(kHeightmapTerrain, "IMAGE", "maps/missing_hills.png") + kWorldEnd);
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  ASSERT_EQ(l.diagnostics.all().size(), 1u) << l.diagnostics.joined();
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<terrain"),
                      {"<terrain> image 'maps/missing_hills.png' not found (looked for " + dir.path().string() +
                           "/maps/missing_hills.png)"}));
}

TEST(ProjectErrors, AFileThatIsNotAnImage) {
  TempDir dir;
  dir.write("hills.png", "This is a text file pretending to be a PNG image.\n");
  const std::string xml =
      replaced(kGoodProject, kWorldEnd, replaced(kHeightmapTerrain, "IMAGE", "hills.png") + kWorldEnd);
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  ASSERT_EQ(l.diagnostics.all().size(), 1u) << l.diagnostics.joined();
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<terrain"),
                      {"<terrain> image 'hills.png'", "cannot read heightmap image", "unknown image type"}));
}

TEST(ProjectErrors, MissingRobotFile) {
  TempDir dir;
  const std::string xml = R"(<?xml version="1.0"?>
<project name="lost_robot">
)" + kWorldForRobotFiles + R"(  <robot file="robots/nowhere.xml">
    <pose x="0" y="0"/>
  </robot>
</project>
)";
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  const std::string looked_for = (dir.path() / "robots" / "nowhere.xml").lexically_normal().string();
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<robot file"),
                      {"robot file 'robots/nowhere.xml' not found", looked_for}));
  // Nothing else: the robot's parts were never read, so they cannot be judged (no "needs 2 wheels,
  // found 0" about a file that may well have them, no missing name).
  EXPECT_EQ(l.diagnostics.all().size(), 1u) << l.diagnostics.joined();
}

TEST(ProjectErrors, MalformedRobotFileNamesTheRobotFileAndItsLine) {
  TempDir dir;
  const std::string robot = R"(<?xml version="1.0"?>
<robot name="broken_bot" drive="differential">
  <chassis shape="box" size="0.3 0.18 0.06" mass="1.5" material="plastic">
  <wheel name="left" pos="0.04 0.11 -0.01" radius="0.045" material="rubber"/>
</robot>
)";
  const std::string robot_path = dir.write("broken_bot.xml", robot);
  const std::string xml = project_including("broken_bot.xml");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  // <chassis ...> on line 3 is never closed.
  EXPECT_TRUE(reports(l.diagnostics, robot_path, line_of(robot, "<chassis"),
                      {"malformed XML: <chassis> is never closed: </robot> on line 5 comes before its </chassis>"}));
  EXPECT_EQ(l.diagnostics.all().size(), 1u) << l.diagnostics.joined();
}

TEST(ProjectErrors, ErrorsInsideARobotFileNameThatFile) {
  TempDir dir;
  const std::string robot = R"(<?xml version="1.0"?>
<robot name="wrong_bot" drive="differential">
  <chassis shape="box" size="0.3 0.18 0.06" mass="0" material="plastic"/>
  <wheel name="left" pos="0.04 0.11 -0.01" radius="0.045" material="rubber"/>
  <wheel name="right" pos="0.04 -0.11 -0.01" radius="0.045" material="rubber"/>
  <caster pos="-0.11 0 -0.035" radius="0.02"/>
  <motor name="left" wheels="left" stall_torque="0.6" no_load_rpm="160"/>
  <motor name="right" wheels="rihgt" stall_torque="0.6" no_load_rpm="160"/>
</robot>
)";
  const std::string robot_path = dir.write("wrong_bot.xml", robot);
  const std::string xml = project_including("wrong_bot.xml");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  ASSERT_EQ(l.diagnostics.all().size(), 2u) << l.diagnostics.joined();
  EXPECT_TRUE(reports(l.diagnostics, robot_path, line_of(robot, "<chassis"),
                      {"<chassis> attribute 'mass'", "out of range", "expected 0.01..100000 kg"}));
  EXPECT_TRUE(reports(l.diagnostics, robot_path, line_of(robot, "<motor name=\"right\""),
                      {"unknown wheel 'rihgt'", "did you mean 'right'"}));
}

TEST(ProjectErrors, UnknownMaterialSuggestsTheNearestName) {
  TempDir dir;
  std::string xml = replaced(kGoodProject, R"(size="0.5 0.5 0.4" material="wood")", R"(size="0.5 0.5 0.4" material="wod")");
  xml = replaced(xml, R"(radius="0.045" width="0.025" mass="0.06" material="rubber"/>
    <wheel name="right")",
                 R"(radius="0.045" width="0.025" mass="0.06" material="rubbr"/>
    <wheel name="right")");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  ASSERT_EQ(l.diagnostics.all().size(), 2u) << l.diagnostics.joined();
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<box"),
                      {"box 'crate' uses unknown material 'wod'", "did you mean 'wood'"}));
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, R"(<wheel name="left")"),
                      {"<wheel> uses unknown material 'rubbr'", "did you mean 'rubber'"}));
}

TEST(ProjectErrors, MotorNamingAnUnknownWheel) {
  TempDir dir;
  const std::string xml = replaced(kGoodProject, R"(<motor name="left_motor" wheels="left")",
                                   R"(<motor name="left_motor" wheels="lefft")");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  ASSERT_EQ(l.diagnostics.all().size(), 1u) << l.diagnostics.joined();
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, R"(<motor name="left_motor")"),
                      {"robot 'bot'", "'left_motor' names unknown wheel 'lefft'", "did you mean 'left'"}));
}

TEST(ProjectErrors, ScriptNamingAnUnknownMotor) {
  TempDir dir;
  const std::string xml = replaced(kGoodProject, R"(<motor t="0" name="right_motor")", R"(<motor t="0" name="rigth_motor")");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  ASSERT_EQ(l.diagnostics.all().size(), 1u) << l.diagnostics.joined();
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, R"(<motor t="0" name="rigth_motor")"),
                      {"script names unknown motor 'rigth_motor'", "did you mean 'right_motor'"}));
}

TEST(ProjectErrors, DifferentialDriveWithThreeWheels) {
  TempDir dir;
  const std::string xml = replaced(
      kGoodProject, "    <caster ",
      R"(    <wheel name="middle" pos="0 0 -0.01" radius="0.045" width="0.025" mass="0.06" material="rubber"/>
    <caster )");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  ASSERT_EQ(l.diagnostics.all().size(), 1u) << l.diagnostics.joined();
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<robot name=\"bot\""),
                      {"robot 'bot'", "drive=\"differential\" needs 2 wheels, found 3"}));
}

TEST(ProjectErrors, MissingProjectFile) {
  TempDir dir;
  const std::string path = (dir.path() / "no_such_project.xml").string();
  Diagnostics diagnostics;
  EXPECT_FALSE(load_project(path, diagnostics).has_value());
  ASSERT_EQ(diagnostics.all().size(), 1u) << diagnostics.joined();
  EXPECT_TRUE(reports(diagnostics, path, 0, {"project file not found"}));
  EXPECT_EQ(diagnostics.all()[0].str(), path + ": error: project file not found");
}

TEST(ProjectErrors, SeveralIndependentErrorsAreAllReported) {
  TempDir dir;
  std::string xml = replaced(kGoodProject, R"(<run duration="5")", R"(<run duration="five")");
  xml = replaced(xml, R"(step="0.001")", R"(step="0.5")");
  xml = replaced(xml, R"(<box name="crate")", R"(<boxx name="crate")");
  xml = replaced(xml, kChassis, R"(<chassis shape="box" size="0.30 0.18 0.06" mass="-2" material="plastic"/>)");
  xml = replaced(xml, kLeftWheel, R"(<wheel name="left" pos="0.04 0.11 -0.01" radius="0")");
  xml = replaced(xml, R"(<motor t="0" name="right_motor")", R"(<motor t="0" name="rigth_motor")");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());

  const std::vector<std::pair<int, std::vector<std::string>>> expected = {
      {line_of(xml, "<run"), {"<run> attribute 'duration'", "expected a number", "'five'"}},
      {line_of(xml, "<world"), {"<world> attribute 'step'", "out of range"}},
      {line_of(xml, "<boxx"), {"unknown element <boxx>", "did you mean 'box'"}},
      {line_of(xml, "<chassis"), {"<chassis> attribute 'mass'", "out of range"}},
      {line_of(xml, R"(<wheel name="left")"), {"<wheel> attribute 'radius'", "out of range"}},
      {line_of(xml, "rigth_motor"), {"unknown motor 'rigth_motor'"}},
  };
  ASSERT_EQ(l.diagnostics.all().size(), expected.size()) << l.diagnostics.joined();
  for (const auto& [line, parts] : expected) EXPECT_TRUE(reports(l.diagnostics, l.path, line, parts));

  std::vector<int> lines;
  for (const auto& d : l.diagnostics.all()) lines.push_back(d.line);
  std::sort(lines.begin(), lines.end());
  EXPECT_EQ(lines, (std::vector<int>{3, 4, 8, 12, 13, 20}));
}

TEST(ProjectErrors, TheBundledDefaultProjectLoadsAsWritten) {
  const std::string path = std::string(SEAR_ASSET_DIR) + "/projects/default.xml";
  Diagnostics diagnostics;
  const std::optional<ProjectDesc> project = load_project(path, diagnostics);
  EXPECT_TRUE(diagnostics.ok()) << diagnostics.joined();
  ASSERT_TRUE(project.has_value());

  EXPECT_EQ(project->name, "default");
  EXPECT_DOUBLE_EQ(project->run.duration_s, 60.0);
  EXPECT_EQ(project->run.seed, 1u);
  EXPECT_DOUBLE_EQ(project->run.trace_rate_hz, 50.0);

  const WorldDesc& world = project->world;
  EXPECT_DOUBLE_EQ(world.step_s, 0.001);
  EXPECT_DOUBLE_EQ(world.gravity.z(), -9.81);
  EXPECT_DOUBLE_EQ(world.gps_origin.latitude_deg, 52.2053);
  EXPECT_DOUBLE_EQ(world.gps_origin.longitude_deg, 0.1218);
  EXPECT_DOUBLE_EQ(world.gps_origin.altitude_m, 12.0);
  EXPECT_NEAR(world.magnetic_declination_rad, 0.9 * kPi / 180.0, 1e-12);
  EXPECT_EQ(world.materials.size(), 7u);  // "default" and the six the file defines

  EXPECT_EQ(world.terrain.kind, TerrainKind::Heightmap);
  EXPECT_EQ(world.terrain.columns, 129);
  EXPECT_EQ(world.terrain.rows, 129);
  ASSERT_EQ(world.terrain.heights_m.size(), 129u * 129u);
  EXPECT_DOUBLE_EQ(world.terrain.size_m.x(), 40.0);
  EXPECT_DOUBLE_EQ(world.terrain.size_m.y(), 40.0);
  const auto [lowest, highest] = std::minmax_element(world.terrain.heights_m.begin(), world.terrain.heights_m.end());
  EXPECT_GE(*lowest, 0.0);
  EXPECT_LE(*highest, 1.2 + 1e-12);
  EXPECT_GT(*highest, *lowest);  // hills, not a plain
  EXPECT_EQ(world.terrain.material, "grass");

  EXPECT_EQ(world.boxes.size(), 3u);
  EXPECT_EQ(world.trees.size(), 2u);
  EXPECT_EQ(world.walls.size(), 4u);  // an arena: north, east, south and west
  ASSERT_EQ(world.meshes.size(), 1u);
  EXPECT_EQ(world.meshes[0].name, "rock");
  EXPECT_FALSE(world.meshes[0].mesh.indices.empty());
  EXPECT_NEAR(world.meshes[0].yaw_rad, 35.0 * kPi / 180.0, 1e-12);

  ASSERT_EQ(project->robots.size(), 1u);
  const RobotDesc& rover = project->robots[0];
  EXPECT_EQ(rover.name, "rover");
  EXPECT_EQ(rover.drive, DriveKind::Differential);
  EXPECT_DOUBLE_EQ(rover.chassis.mass_kg, 1.5);
  ASSERT_EQ(rover.wheels.size(), 2u);
  for (const auto& wheel : rover.wheels) {
    EXPECT_DOUBLE_EQ(wheel.radius_m, 0.045);
    EXPECT_DOUBLE_EQ(wheel.width_m, 0.025);
    EXPECT_EQ(fs::path(wheel.source.file).filename(), "rover.xml");
  }
  EXPECT_EQ(rover.wheels[0].name, "left");
  EXPECT_DOUBLE_EQ(rover.wheels[0].position_m.y(), 0.11);
  EXPECT_EQ(rover.casters.size(), 1u);
  ASSERT_EQ(rover.motors.size(), 2u);
  for (const auto& motor : rover.motors) {
    EXPECT_NEAR(motor.no_load_speed_radps, 160.0 * 2.0 * kPi / 60.0, 1e-9);
    EXPECT_DOUBLE_EQ(motor.stall_torque_nm, 0.6);
  }
  // Firmware drives it: the reference rover on one MCU, compiled from its sources and the shared
  // drivers, with every sensor kind wired.
  EXPECT_TRUE(rover.script.empty());
  ASSERT_EQ(rover.mcus.size(), 1u);
  const McuDesc& mcu = rover.mcus[0];
  EXPECT_EQ(mcu.name, "main");
  ASSERT_EQ(mcu.firmware_sources.size(), 9u);
  EXPECT_EQ(fs::path(mcu.firmware_sources[0]).filename(), "rover.c");
  for (const auto& source : mcu.firmware_sources) EXPECT_TRUE(fs::exists(source)) << source;
  ASSERT_EQ(mcu.devices.size(), 10u);
  EXPECT_STREQ(mcu.devices[0].kind->element, "gp2d12");
  EXPECT_EQ(mcu.devices[0].wire("adc"), 0);
  EXPECT_NEAR(mcu.devices[0].yaw_rad, 30 * kPi / 180, 1e-12);
  EXPECT_STREQ(mcu.devices[2].kind->element, "bump");
  EXPECT_EQ(mcu.devices[2].wire("pin"), 2);
  EXPECT_STREQ(mcu.devices[4].kind->element, "lms2xx");
  EXPECT_EQ(mcu.devices[4].wire("uart"), 1);
  EXPECT_STREQ(mcu.devices[6].kind->element, "mpu6000");
  EXPECT_EQ(mcu.devices[6].wire("cs"), 53);
  ASSERT_EQ(mcu.motors.size(), 2u);
  EXPECT_EQ(mcu.motors[0].motor, "left");
  EXPECT_EQ(mcu.motors[0].pwm_pin, 3);
  EXPECT_EQ(mcu.motors[0].dir_pin, 12);
  EXPECT_EQ(mcu.motors[0].brake_pin, 9);
}

TEST(ProjectErrors, LatitudeLongitudePoseLandsWhereTheTangentPlaneSays) {
  TempDir dir;
  const std::string rover = std::string(SEAR_ASSET_DIR) + "/robots/rover.xml";
  const std::string xml = R"(<?xml version="1.0"?>
<project name="geo">
  <world step="0.001">
    <gps_origin latitude="52.2053" longitude="0.1218" altitude="12"/>
    <material name="rubber" friction="1.0"/>
    <material name="plastic" friction="0.4"/>
  </world>
  <robot file=")" + rover + R"(">
    <pose latitude="52.2062" longitude="0.1232" yaw_deg="90"/>
  </robot>
</project>
)";
  const Loaded l = load(dir, xml);
  EXPECT_TRUE(l.diagnostics.ok()) << l.diagnostics.joined();
  ASSERT_TRUE(l.project.has_value());
  ASSERT_EQ(l.project->robots.size(), 1u);
  const RobotDesc& robot = l.project->robots[0];
  EXPECT_EQ(robot.name, "rover");

  const Enu expected = LocalTangentPlane({52.2053, 0.1218, 12}).to_enu({52.2062, 0.1232, 12});
  EXPECT_NEAR(robot.start_xy_m.x(), expected.east_m, 1e-9);
  EXPECT_NEAR(robot.start_xy_m.y(), expected.north_m, 1e-9);
  // Independently, roughly: 0.0009 degrees of latitude is ~100 m north, 0.0014 degrees of longitude
  // at 52.2 degrees is ~96 m east (111.3 km per degree times cos(latitude)).
  EXPECT_NEAR(robot.start_xy_m.y(), 0.0009 * 111.26e3, 1.0);
  EXPECT_NEAR(robot.start_xy_m.x(), 0.0014 * 111.32e3 * std::cos(52.2058 * kPi / 180.0), 1.0);
  EXPECT_NEAR(robot.start_yaw_rad, kPi / 2.0, 1e-12);
}

TEST(ProjectErrors, NamesMustBeUsableAsFileNames) {
  TempDir dir;
  // Robot names become trace file names: a path in one must not reach outside the output folder.
  const std::string xml = replaced(kGoodProject, R"(<robot name="bot")", R"(<robot name="../bot")");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<robot name"),
                      {"name '../bot': use letters, digits, '_' and '-' only"}));
}

TEST(ProjectErrors, ObstacleAndRobotNamesAreUnique) {
  TempDir dir;
  const std::string xml = replaced(kGoodProject, kWorldEnd, R"(    <wall name="bot" from="0 5" to="5 5"/>
    <box name="crate" pos="-3 0" size="1 1 1"/>
)" + kWorldEnd);
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  EXPECT_EQ(l.diagnostics.all().size(), 2u) << l.diagnostics.joined();
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, R"(<box name="crate" pos="-3)"),
                      {"box name 'crate' is already used"}));
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<robot name"), {"robot name 'bot' is already used"}));
}

TEST(ProjectErrors, ARobotNeedsOneChassisAndOnePose) {
  TempDir dir;
  std::string xml = replaced(kGoodProject, "    " + kChassis + "\n", "");
  xml = replaced(xml, R"(    <pose x="1" y="2" yaw_deg="0"/>)", R"(    <pose x="1" y="2" yaw_deg="0"/>
    <pose x="5" y="5"/>)");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<robot name"), {"<robot> needs a <chassis>"}));
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, R"(<pose x="5")"),
                      {"<pose> may appear only once in <robot> (first at line " +
                       std::to_string(line_of(xml, R"(<pose x="1")")) + ")"}));
}

TEST(ProjectErrors, SteeredTakesTrueOrFalseOnly) {
  TempDir dir;
  const std::string xml = replaced(kGoodProject, kLeftWheel, kLeftWheel + R"( steered="yes")");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, kLeftWheel), {"'steered': 'yes' is not one of false, true"}));
}

TEST(ProjectErrors, AckermannSteersTheFrontAndServosCannotDriveSteeredWheels) {
  TempDir dir;
  // The bundled car with its steered wheels moved behind the driven ones, and a continuous
  // servo on a steered wheel.
  std::string car = dir.write("car.xml", R"(<robot name="car" drive="ackermann">
  <material name="rubber" friction="1.0"/>
  <chassis shape="box" size="0.40 0.18 0.06" mass="1.8"/>
  <wheel name="fl" pos="-0.13 0.10 -0.02" radius="0.05" steered="true" material="rubber"/>
  <wheel name="fr" pos="-0.13 -0.10 -0.02" radius="0.05" steered="true" material="rubber"/>
  <wheel name="rl" pos="0.13 0.10 -0.02" radius="0.05" material="rubber"/>
  <wheel name="rr" pos="0.13 -0.10 -0.02" radius="0.05" material="rubber"/>
  <servo name="steering" kind="positional" steers="fl fr"/>
  <servo name="spin" kind="continuous" wheels="fl"/>
  <motor name="drive" wheels="rl rr" stall_torque="1" no_load_rpm="300"/>
</robot>
)");
  const std::string xml = project_including("car.xml");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  EXPECT_TRUE(reports(l.diagnostics, car, 1, {"steers the front wheels"}));  // where drive= is written
  EXPECT_TRUE(reports(l.diagnostics, car, 9, {"continuous servo 'spin' cannot drive steered wheel 'fl'"}));
}

TEST(ProjectErrors, TimesBeyondTenMillionSecondsAreRejected) {
  TempDir dir;
  const std::string xml = replaced(kGoodProject, R"(<run duration="5")", R"(<run duration="1e300")");
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, "<run"), {"'duration': 1e300 s is out of range"}));
}

TEST(ProjectErrors, MotorVoltagesAreRead) {
  TempDir dir;
  const std::string xml = replaced(kGoodProject, R"(<motor name="left_motor" wheels="left")",
                                   R"(<motor name="left_motor" wheels="left" rated_voltage="6" supply_voltage="9")");
  const Loaded l = load(dir, xml);
  ASSERT_TRUE(l.project.has_value()) << l.diagnostics.joined();
  EXPECT_EQ(l.project->robots[0].motors[0].rated_voltage_v, 6.0);
  EXPECT_EQ(l.project->robots[0].motors[0].supply_voltage_v, 9.0);
  EXPECT_EQ(l.project->robots[0].motors[1].supply_voltage_v, l.project->robots[0].motors[1].rated_voltage_v);

  // A supply voltage alone means the figures were measured at that voltage.
  const Loaded only_supply = load(dir, replaced(kGoodProject, R"(<motor name="left_motor" wheels="left")",
                                                R"(<motor name="left_motor" wheels="left" supply_voltage="12")"));
  ASSERT_TRUE(only_supply.project.has_value()) << only_supply.diagnostics.joined();
  EXPECT_EQ(only_supply.project->robots[0].motors[0].rated_voltage_v, 12.0);
}

TEST(ProjectErrors, AnIncludedRobotTakesOnePoseAndOneScript) {
  TempDir dir;
  dir.write("bot.xml", "<robot name=\"bot\" drive=\"differential\">\n" +
                           std::string(R"(  <material name="rubber"/><material name="plastic"/>
  <chassis size="0.3 0.18 0.06" mass="1.5" material="plastic"/>
  <wheel name="left" pos="0 0.1 0" radius="0.04" material="rubber"/>
  <wheel name="right" pos="0 -0.1 0" radius="0.04" material="rubber"/>
  <caster pos="-0.1 0 -0.02" radius="0.02"/>
</robot>
)"));
  const std::string xml = R"(<project>
  <world/>
  <robot file="bot.xml">
    <pose x="0" y="0"/>
    <pose x="1" y="0"/>
  </robot>
</project>
)";
  const Loaded l = load(dir, xml);
  EXPECT_FALSE(l.project.has_value());
  EXPECT_TRUE(reports(l.diagnostics, l.path, line_of(xml, R"(<pose x="1")"), {"<pose> may appear only once in <robot>"}));
}

}  // namespace
}  // namespace sear
