// Every firmware example carries scenarios that check what it is for, and they pass as CI runs them:
// `sear test firmware_examples --junit FILE`, its JUnit report read back case by case against the
// scenario files; and the avoider's scenario turns red for a firmware that stalls.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <tinyxml2.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "firmware_run.hpp"

namespace sear::test {
namespace {

namespace fs = std::filesystem;

const fs::path kExamples = SEAR_EXAMPLES_DIR;

int exit_code(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : -1; }

// An example is a folder with C sources of its own (rover's project is assets/projects/default.xml).
std::vector<fs::path> example_folders() {
  std::vector<fs::path> folders;
  for (const auto& entry : fs::directory_iterator(kExamples)) {
    if (!entry.is_directory() || entry.path().filename() == "lib") continue;
    for (const auto& file : fs::directory_iterator(entry.path()))
      if (file.path().extension() == ".c") {
        folders.push_back(entry.path());
        break;
      }
  }
  return folders;
}

std::vector<fs::path> scenario_files(const fs::path& folder) {
  std::vector<fs::path> files;
  for (const auto& file : fs::directory_iterator(folder)) {
    const std::string name = file.path().filename().string();
    if (name.rfind("scenario_", 0) == 0 && file.path().extension() == ".xml") files.push_back(file.path());
  }
  return files;
}

// The names of a scenario file's expectations, in order; empty for one left to its default name
// (mcu_running, no_collision: "mcu rover.main keeps running").
std::vector<std::string> expectation_names(const fs::path& scenario) {
  tinyxml2::XMLDocument doc;
  EXPECT_EQ(doc.LoadFile(scenario.c_str()), tinyxml2::XML_SUCCESS) << scenario;
  std::vector<std::string> names;
  const auto* root = doc.RootElement();
  const auto* expect = root ? root->FirstChildElement("expect") : nullptr;
  if (!expect) return names;
  for (const auto* e = expect->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const char* name = e->Attribute("name");
    names.push_back(name ? name : "");
  }
  return names;
}

TEST(ExampleScenarios, EveryExampleHasAScenarioThatWatchesItsMcus) {
  const auto folders = example_folders();
  // avoider, blink, can_nodes, dead_reckoning, gps_waypoints, hcsr04_ping, imu_heading,
  // maxbotix_three, rover, wall_follower: an example added without a scenario fails here.
  EXPECT_GE(folders.size(), 10u);
  for (const auto& folder : folders) {
    const auto files = scenario_files(folder);
    EXPECT_FALSE(files.empty()) << folder.filename() << " has no scenario_*.xml";
    for (const auto& file : files) {
      tinyxml2::XMLDocument doc;
      ASSERT_EQ(doc.LoadFile(file.c_str()), tinyxml2::XML_SUCCESS) << file;
      const auto* expect = doc.RootElement()->FirstChildElement("expect");
      ASSERT_NE(expect, nullptr) << file;
      EXPECT_NE(expect->FirstChildElement("mcu_running"), nullptr) << file << " does not check that its MCU keeps running";
      // Something about what the example does, besides its MCU running.
      EXPECT_GE(expectation_names(file).size(), 3u) << file;
    }
  }
}

// The whole suite, as CI runs it; its report has one test suite per scenario and one test case per
// expectation, named as the scenario file names them, none failed.
TEST(ExampleScenarios, AllPassUnderSearTestWithOneTestCasePerExpectation) {
  TempDir dir;
  const fs::path junit = dir.path() / "report.xml";
  const std::string cmd = std::string(SEAR_BINARY) + " test " + kExamples.string() + " -j 2 --junit " + junit.string() +
                          " -o " + (dir.path() / "out").string() + " >" + (dir.path() / "stdout").string() + " 2>&1";
  EXPECT_EQ(exit_code(std::system(cmd.c_str())), 0) << read_file(dir.path() / "stdout");

  std::map<std::string, std::vector<std::string>> wanted;  // scenario path relative to firmware_examples
  std::size_t total = 0;
  for (const auto& folder : example_folders())
    for (const auto& file : scenario_files(folder)) {
      auto& names = wanted[fs::relative(file, kExamples).generic_string()];
      names = expectation_names(file);
      total += names.size();
    }

  tinyxml2::XMLDocument doc;
  ASSERT_EQ(doc.LoadFile(junit.c_str()), tinyxml2::XML_SUCCESS) << read_file(dir.path() / "stdout");
  const auto* suites = doc.RootElement();
  EXPECT_EQ(suites->IntAttribute("tests", -1), static_cast<int>(total));
  EXPECT_EQ(suites->IntAttribute("failures", -1), 0);
  EXPECT_EQ(suites->IntAttribute("errors", -1), 0);
  std::set<std::string> seen;
  for (const auto* suite = suites->FirstChildElement("testsuite"); suite; suite = suite->NextSiblingElement("testsuite")) {
    std::string scenario;
    if (const auto* props = suite->FirstChildElement("properties"))
      for (const auto* p = props->FirstChildElement("property"); p; p = p->NextSiblingElement("property"))
        if (std::string(p->Attribute("name")) == "scenario") scenario = p->Attribute("value");
    ASSERT_TRUE(wanted.count(scenario)) << "a test suite for an unknown scenario: '" << scenario << "'";
    EXPECT_TRUE(seen.insert(scenario).second) << scenario << " reported twice";
    std::vector<std::string> cases;
    for (const auto* c = suite->FirstChildElement("testcase"); c; c = c->NextSiblingElement("testcase")) {
      cases.push_back(c->Attribute("name"));
      EXPECT_EQ(c->FirstChildElement("failure"), nullptr) << scenario << ": " << cases.back();
    }
    const auto& names = wanted[scenario];
    ASSERT_EQ(cases.size(), names.size()) << scenario;
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (!names[i].empty()) {
        EXPECT_EQ(cases[i], names[i]) << scenario << ", expectation " << i + 1;
      }
    }
  }
  EXPECT_EQ(seen.size(), wanted.size());
}

// The avoider's scenario against its own firmware with the motors' duties at 0 (a firmware that
// stalls): the three regions and the veer fail; it still runs and touches nothing.
TEST(ExampleScenarios, TheAvoidersScenarioFailsForAFirmwareThatStalls) {
  TempDir dir;
  std::string source = read_file(kExamples / "avoider" / "avoider.c");
  for (const std::string constant : {"#define CRUISE 150", "#define TURN 130"}) {
    const auto at = source.find(constant);
    ASSERT_NE(at, std::string::npos) << constant;
    source.replace(at, constant.size(), constant.substr(0, constant.rfind(' ')) + " 0");
  }
  std::ofstream(dir.path() / "avoider.c") << source;
  std::string project = read_file(kExamples / "avoider" / "project.xml");
  const std::string robot = "../../assets/robots/rover.xml";
  ASSERT_NE(project.find(robot), std::string::npos);
  project.replace(project.find(robot), robot.size(), std::string(SEAR_ASSET_DIR) + "/robots/rover.xml");
  std::ofstream(dir.path() / "project.xml") << project;
  fs::copy_file(kExamples / "avoider" / "scenario_room.xml", dir.path() / "scenario_room.xml");

  const fs::path junit = dir.path() / "report.xml";
  const std::string cmd = std::string(SEAR_BINARY) + " run " + (dir.path() / "scenario_room.xml").string() + " -q -o " +
                          (dir.path() / "out").string() + " --junit " + junit.string() + " 2>" +
                          (dir.path() / "stderr").string();
  EXPECT_EQ(exit_code(std::system(cmd.c_str())), 5) << read_file(dir.path() / "stderr");
  tinyxml2::XMLDocument doc;
  ASSERT_EQ(doc.LoadFile(junit.c_str()), tinyxml2::XML_SUCCESS) << read_file(dir.path() / "stderr");
  std::set<std::string> failed, passed;
  const auto* suite = doc.RootElement()->FirstChildElement("testsuite");
  ASSERT_NE(suite, nullptr);
  for (const auto* c = suite->FirstChildElement("testcase"); c; c = c->NextSiblingElement("testcase"))
    (c->FirstChildElement("failure") ? failed : passed).insert(c->Attribute("name"));
  EXPECT_EQ(failed, (std::set<std::string>{"veers right for the crate", "south-east quarter", "south-west quarter",
                                           "west side, north of the start"}));
  EXPECT_EQ(passed, (std::set<std::string>{"mcu rover.main keeps running", "no collision rover"}));
}

}  // namespace
}  // namespace sear::test
