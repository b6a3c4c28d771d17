// Expectations through `sear run` as CI runs it: a scenario file naming a project, the exit code
// of its own (5), the run ending once every verdict is known, the JUnit report read back, and an
// MCU that crashes turning its mcu_running expectation red.
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <nlohmann/json.hpp>

#include "firmware_run.hpp"

namespace sear::test {
namespace {

// Two MCUs on one bus (the CAN probes of can_run_test.cpp): at 10 ms each sends one frame, and
// each prints the other's as "rx <us> <id> ..." once its quantum after the frame's end begins.
std::string project() {
  return "<project name=\"expect\">\n  <run duration=\"1\" seed=\"1\" trace_rate=\"10\"/>\n"
         "  <can_bus name=\"body\" bitrate=\"500000\"/>\n  <world step=\"0.001\">\n    <terrain type=\"flat\"/>\n"
         "  </world>\n  <robot file=\"" SEAR_ASSET_DIR "/robots/rover.xml\">\n    <pose x=\"0\" y=\"0\"/>\n"
         "    <mcu name=\"a\"><firmware executable=\"" CAN_PROBE_200 "\"/><can bus=\"body\"/></mcu>\n"
         "    <mcu name=\"b\"><firmware executable=\"" CAN_PROBE_100 "\"/><can bus=\"body\"/></mcu>\n"
         "    <mcu name=\"c\"><firmware executable=\"" CRASH_PROBE "\"/></mcu>\n  </robot>\n</project>\n";
}

struct ScenarioRun {
  SearRun run;
  nlohmann::json summary;
  tinyxml2::XMLDocument junit;
};

void run_scenario(const TempDir& dir, const std::string& expect, double timeout_s, ScenarioRun& out) {
  std::ofstream(dir.path() / "project.xml") << project();
  std::ofstream(dir.path() / "scenario.xml") << "<scenario name=\"probe\" project=\"project.xml\" timeout=\"" << timeout_s
                                             << "\">\n  <expect>\n" << expect << "  </expect>\n</scenario>\n";
  const std::string cmd = std::string(SEAR_BINARY) + " run " + (dir.path() / "scenario.xml").string() + " -q -o " +
                          (dir.path() / "out").string() + " --junit " + (dir.path() / "junit.xml").string() + " 2>" +
                          (dir.path() / "stderr").string();
  const int status = std::system(cmd.c_str());
  out.run = {WIFEXITED(status) ? WEXITSTATUS(status) : -1, "", read_file(dir.path() / "stderr"), dir.path() / "out"};
  out.summary = nlohmann::json::parse(out.run.file("summary.json"));
  ASSERT_EQ(out.junit.LoadFile((dir.path() / "junit.xml").c_str()), tinyxml2::XML_SUCCESS) << out.run.err;
}

int failures(const tinyxml2::XMLDocument& junit) { return junit.RootElement()->IntAttribute("failures", -1); }

TEST(ExpectRun, PassingExpectationsEndTheRunOnceDecided) {
  TempDir dir;
  ScenarioRun r;
  // The frame 0x100 ends 0.23 ms after 10 ms and reaches "a" when the quantum after it begins:
  // seen by 12 ms. The robot sits at the origin. Both decided by ~11 ms, far before the 10 s timeout.
  run_scenario(dir,
               "    <console mcu=\"rover.a\" matches=\"^rx [0-9]+ 100 8 0011223344556677$\" before=\"0.012\"/>\n"
               "    <region robot=\"rover\" shape=\"circle\" center=\"0 0\" radius=\"0.1\" before=\"0.005\"/>\n",
               10, r);
  EXPECT_EQ(r.run.exit_code, 0) << r.run.err;
  EXPECT_LT(r.summary["sim_time_s"].get<double>(), 0.02);  // it stopped once both were known
  EXPECT_EQ(failures(r.junit), 0);
  EXPECT_EQ(r.junit.RootElement()->IntAttribute("tests"), 2);
  ASSERT_EQ(r.summary["expectations"].size(), 2u);
  EXPECT_EQ(r.summary["expectations"][0]["verdict"], "passed");
}

TEST(ExpectRun, AFailedExpectationHasItsOwnExitCodeAndSaysWhatWasSeen) {
  TempDir dir;
  ScenarioRun r;
  run_scenario(dir,
               "    <console mcu=\"rover.a\" matches=\"^rx [0-9]+ 300 \" before=\"0.05\"/>\n"
               "    <region robot=\"rover\" shape=\"box\" min=\"1 1\" max=\"2 2\" before=\"0.05\"/>\n",
               0.2, r);
  EXPECT_EQ(r.run.exit_code, 5) << r.run.err;
  EXPECT_EQ(failures(r.junit), 2);
  // Both decided at their deadline, so the run ends there, not at the 0.2 s timeout.
  EXPECT_NEAR(r.summary["sim_time_s"].get<double>(), 0.05, 0.003);
  const tinyxml2::XMLElement* suite = r.junit.RootElement()->FirstChildElement("testsuite");
  ASSERT_NE(suite, nullptr);
  std::string messages;
  for (auto* c = suite->FirstChildElement("testcase"); c; c = c->NextSiblingElement("testcase"))
    if (auto* f = c->FirstChildElement("failure")) messages += std::string(f->Attribute("message")) + "\n";
  // The robot stays at the origin: its nearest approach to the box's corner (1, 1) is sqrt(2) m.
  EXPECT_NE(messages.find("1.41 m"), std::string::npos) << messages;
  EXPECT_NE(r.run.err.find("expectation failed at 0.050 s"), std::string::npos) << r.run.err;
  const tinyxml2::XMLElement* out = suite->FirstChildElement("system-out");
  ASSERT_NE(out, nullptr);
  EXPECT_NE(std::string(out->GetText()).find("== rover.a console =="), std::string::npos);
}

TEST(ExpectRun, AnMcuThatCrashesFailsItsRunningExpectation) {
  TempDir dir;
  ScenarioRun r;
  run_scenario(dir, "    <mcu_running mcu=\"rover.c\"/>\n", 1, r);
  // The crash probe stops at 300 ms: the expectation fails then, and its exit code wins over 3.
  EXPECT_EQ(r.run.exit_code, 5) << r.run.err;
  ASSERT_EQ(r.summary["expectations"].size(), 1u);
  EXPECT_EQ(r.summary["expectations"][0]["verdict"], "failed");
  EXPECT_NEAR(r.summary["expectations"][0]["time_s"].get<double>(), 0.3, 0.002);
  EXPECT_NE(r.summary["expectations"][0]["seen"].get<std::string>().find("crashed"), std::string::npos);
}

TEST(ExpectRun, AMistakeInAnExpectationIsAnErrorAtItsLine) {
  TempDir dir;
  std::ofstream(dir.path() / "project.xml") << project();
  std::ofstream(dir.path() / "scenario.xml")
      << "<scenario project=\"project.xml\">\n  <expect>\n    <console mcu=\"rover.x\" never=\"a\"/>\n  </expect>\n</scenario>\n";
  const std::string cmd = std::string(SEAR_BINARY) + " run " + (dir.path() / "scenario.xml").string() + " -q -o " +
                          (dir.path() / "out").string() + " 2>" + (dir.path() / "stderr").string();
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  const std::string err = read_file(dir.path() / "stderr");
  EXPECT_NE(err.find("scenario.xml:3:"), std::string::npos) << err;
  EXPECT_NE(err.find("rover.x"), std::string::npos) << err;
}

}  // namespace
}  // namespace sear::test
