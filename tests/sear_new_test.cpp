// `sear new`: each template's project runs as written with every expectation of its <expect>
// passing (counted in the JUnit report), its CMakeLists.txt builds the firmware for the simulator
// (and that build runs) and for the ATmega2560, and a folder in use is refused untouched.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <tinyxml2.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>

#include "command_output.hpp"
#include "temp_dir.hpp"

namespace sear {
namespace {

namespace fs = std::filesystem;

using Result = test::CommandOutput;  // out: standard output and error together

// Runs a shell command; every path quoted in it is a temporary folder's, which holds no quote.
Result shell(const std::string& command) { return test::command_output(command + " 2>&1"); }

std::string in_quotes(const fs::path& path) { return "'" + path.string() + "'"; }

std::string sear(const std::string& args) { return std::string(SEAR_BINARY) + " " + args; }

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// How many expectations the project's <expect> lists: each one is a test case of the report.
int expectation_count(const fs::path& project) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(project.string().c_str()) != tinyxml2::XML_SUCCESS) return -1;
  const auto* expect = doc.RootElement() ? doc.RootElement()->FirstChildElement("expect") : nullptr;
  int n = 0;
  for (const auto* e = expect ? expect->FirstChildElement() : nullptr; e; e = e->NextSiblingElement()) ++n;
  return n;
}

struct Verdicts {
  int tests = -1;
  int failures = -1;
};

Verdicts junit_verdicts(const fs::path& report) {
  tinyxml2::XMLDocument doc;
  Verdicts v;
  if (doc.LoadFile(report.string().c_str()) != tinyxml2::XML_SUCCESS) return v;
  const auto* suites = doc.RootElement();
  if (!suites) return v;
  v.tests = suites->IntAttribute("tests", -1);
  v.failures = suites->IntAttribute("failures", -1) + suites->IntAttribute("errors", 0);
  return v;
}

// Simulated seconds each template's expectations are all decided by (the rover's last is due at
// 3.5 s, the avoider's at 4 s).
constexpr const char* kShortRun = "5";

// `sear run PROJECT` for kShortRun seconds, its output and JUnit report (report.xml) in `work`.
Result short_run(const fs::path& project, const fs::path& work) {
  return shell(sear("run " + in_quotes(project) + " -q -d " + kShortRun + " -o " + in_quotes(work / "out") +
                    " --junit " + in_quotes(work / "report.xml")));
}

class SearNew : public ::testing::TestWithParam<const char*> {
 protected:
  // `sear new` into a fresh folder, named after the template.
  fs::path make_project() {
    const std::string name = std::string("probe_") + GetParam();
    const fs::path dir = temp_.path() / name;
    const Result made = shell(sear("new " + in_quotes(dir) + " --template " + GetParam()));
    EXPECT_EQ(made.exit_code, 0) << made.out;
    return dir;
  }
  test::TempDir temp_;
};

TEST_P(SearNew, WritesAProjectWhoseExpectationsPass) {
  const fs::path dir = make_project();
  const std::string name = dir.filename().string();
  for (const char* file : {"main.c", "project.xml", "robot.xml", "CMakeLists.txt", "README.md", ".gitignore"})
    EXPECT_TRUE(fs::is_regular_file(dir / file)) << file;
  // Every placeholder was filled in, the name where the templates put it.
  for (const char* file : {"main.c", "project.xml", "CMakeLists.txt", "README.md"}) {
    const std::string text = read_file(dir / file);
    EXPECT_FALSE(std::regex_search(text, std::regex("@[A-Z_]+@"))) << file;
  }
  EXPECT_NE(read_file(dir / "project.xml").find("<project name=\"" + name + "\">"), std::string::npos);
  EXPECT_NE(read_file(dir / "CMakeLists.txt").find("sear_add_firmware(" + name + " SOURCES main.c)"),
            std::string::npos);
  EXPECT_EQ(read_file(dir / "robot.xml"), read_file(fs::path(SEAR_ASSET_DIR) / "robots" / "rover.xml"));

  const int expected = expectation_count(dir / "project.xml");
  ASSERT_GE(expected, 3) << "a template shows a new user how to write expectations";
  const fs::path report = temp_.path() / "report.xml";
  const Result run = short_run(dir, temp_.path());
  EXPECT_EQ(run.exit_code, 0) << run.out;
  const Verdicts v = junit_verdicts(report);
  EXPECT_EQ(v.tests, expected) << read_file(report);
  EXPECT_EQ(v.failures, 0) << read_file(report);

  // The files the templates' comments send a reader to are the ones the run wrote, in the folder
  // `sear run .` writes by default.
  for (const char* file : {"main.c", "project.xml", "README.md"}) {
    const std::string text = read_file(dir / file);
    std::size_t named = 0;
    const std::regex output_file("[A-Za-z0-9_.]+\\.(log|csv|json|vcd)\\b");
    for (std::sregex_iterator m(text.begin(), text.end(), output_file), end; m != end; ++m, ++named)
      EXPECT_TRUE(fs::exists(temp_.path() / "out" / m->str())) << file << " names " << m->str();
    EXPECT_GE(named, 1u) << file << " names none of the run's files";
    const std::regex folder("sear-out/([^/ `]*)");
    for (std::sregex_iterator m(text.begin(), text.end(), folder), end; m != end; ++m)
      EXPECT_EQ((*m)[1].str(), name) << file << ": " << m->str();
  }
}

TEST_P(SearNew, CMakeBuildsTheFirmwareForTheSimulatorAndItRuns) {
  const fs::path dir = make_project();
  const std::string name = dir.filename().string();
  const fs::path build = temp_.path() / "build";
  const Result configured = shell(std::string(CMAKE_COMMAND) + " -S " + in_quotes(dir) + " -B " + in_quotes(build));
  ASSERT_EQ(configured.exit_code, 0) << configured.out;
  const Result built = shell(std::string(CMAKE_COMMAND) + " --build " + in_quotes(build));
  ASSERT_EQ(built.exit_code, 0) << built.out;
  EXPECT_EQ(built.out.find("warning"), std::string::npos) << built.out;
  ASSERT_TRUE(fs::is_regular_file(build / name));

  // The same project running the executable CMake built instead of compiling main.c itself.
  std::string project = read_file(dir / "project.xml");
  const std::string sources = "<firmware sources=\"main.c\"/>";
  const auto at = project.find(sources);
  ASSERT_NE(at, std::string::npos);
  project.replace(at, sources.size(), "<firmware executable=\"" + (build / name).string() + "\"/>");
  const fs::path built_project = dir / "built.xml";
  std::ofstream(built_project) << project;
  const fs::path report = temp_.path() / "report.xml";
  const Result run = short_run(built_project, temp_.path());
  EXPECT_EQ(run.exit_code, 0) << run.out;
  EXPECT_EQ(junit_verdicts(report).tests, expectation_count(dir / "project.xml"));
  EXPECT_EQ(junit_verdicts(report).failures, 0) << read_file(report);
}

TEST_P(SearNew, CMakeBuildsTheFirmwareForTheATmega2560) {
  if (std::string(AVR_GCC).empty()) GTEST_SKIP() << "avr-gcc is not installed (gcc-avr, avr-libc, binutils-avr)";
  const fs::path dir = make_project();
  const std::string name = dir.filename().string();
  const fs::path build = temp_.path() / "build-avr";
  const fs::path toolchain = fs::path(SEAR_SOURCE_DIR) / "cmake" / "avr-gcc.cmake";
  const Result configured = shell(std::string(CMAKE_COMMAND) + " -S " + in_quotes(dir) + " -B " + in_quotes(build) +
                                  " -DCMAKE_TOOLCHAIN_FILE=" + in_quotes(toolchain));
  ASSERT_EQ(configured.exit_code, 0) << configured.out;
  const Result built = shell(std::string(CMAKE_COMMAND) + " --build " + in_quotes(build) + " -j2");
  ASSERT_EQ(built.exit_code, 0) << built.out;
  EXPECT_EQ(built.out.find("warning"), std::string::npos) << built.out;
  // avr-size's report for the chip, and an Intel HEX file for the programmer: records of
  // ':' + hex digits, the last one the end-of-file record.
  EXPECT_NE(built.out.find("Device: atmega2560"), std::string::npos) << built.out;
  const std::string hex = read_file(build / (name + ".hex"));
  ASSERT_FALSE(hex.empty());
  EXPECT_TRUE(std::regex_search(hex, std::regex("^:[0-9A-F]{10,}\r?\n")));
  EXPECT_NE(hex.find(":00000001FF"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Templates, SearNew, ::testing::Values("avoider", "rover", "sensors"));

// The expectations are live: the avoider with its motors idle never reaches the region east of
// its start, and `sear run` says so with exit code 5.
TEST(SearNewExpectations, AStalledAvoiderFails) {
  test::TempDir temp;
  const fs::path dir = temp.path() / "stalled";
  ASSERT_EQ(shell(sear("new " + in_quotes(dir))).exit_code, 0);
  std::string firmware = read_file(dir / "main.c");
  const std::string cruise = "#define CRUISE 150";
  const auto at = firmware.find(cruise);
  ASSERT_NE(at, std::string::npos);
  firmware.replace(at, cruise.size(), "#define CRUISE 0");
  std::ofstream(dir / "main.c") << firmware;
  const fs::path report = temp.path() / "report.xml";
  const Result run = short_run(dir, temp.path());
  EXPECT_EQ(run.exit_code, 5) << run.out;
  EXPECT_NE(run.out.find("region rover"), std::string::npos) << run.out;
  EXPECT_EQ(junit_verdicts(report).failures, 1) << read_file(report);
}

TEST(SearNewFolder, RefusesAFolderInUseAndLeavesItAlone) {
  test::TempDir temp;
  const std::string kept = temp.write("used/main.c", "int main(void) { return 0; }\n");
  const Result refused = shell(sear("new " + in_quotes(temp.path() / "used")));
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.out.find("is not empty"), std::string::npos) << refused.out;
  EXPECT_EQ(read_file(kept), "int main(void) { return 0; }\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(temp.path() / "used"), fs::directory_iterator()), 1);

  const std::string file = temp.write("a_file", "x");
  const Result not_a_folder = shell(sear("new " + in_quotes(file)));
  EXPECT_EQ(not_a_folder.exit_code, 1);
  EXPECT_NE(not_a_folder.out.find("not a folder"), std::string::npos) << not_a_folder.out;
  EXPECT_EQ(read_file(file), "x");
}

TEST(SearNewFolder, FillsAnEmptyFolderNamedAfterIt) {
  test::TempDir temp;
  const fs::path dir = temp.path() / "my-bot";
  fs::create_directory(dir);
  const Result made = shell(sear("new " + in_quotes(dir) + "/ -t rover"));  // a trailing slash too
  ASSERT_EQ(made.exit_code, 0) << made.out;
  EXPECT_NE(read_file(dir / "project.xml").find("<project name=\"my-bot\">"), std::string::npos);
  EXPECT_NE(read_file(dir / "CMakeLists.txt").find("project(my-bot LANGUAGES C)"), std::string::npos);

  // --name wins over the folder's; a name CMake or the project file would refuse is refused.
  const Result named = shell(sear("new " + in_quotes(temp.path() / "x") + " --name wanderer"));
  ASSERT_EQ(named.exit_code, 0) << named.out;
  EXPECT_NE(read_file(temp.path() / "x" / "main.c").find("\"wanderer: ready"), std::string::npos);
  const Result bad = shell(sear("new " + in_quotes(temp.path() / "y") + " --name '2 fast'"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_FALSE(fs::exists(temp.path() / "y"));
}

}  // namespace
}  // namespace sear
