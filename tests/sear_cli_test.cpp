// The `sear` program as a user runs it: determinism across processes, outputs, errors, Ctrl-C.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Result {
  int exit_code;
  std::string out;
  std::string err;
};

// Runs `sear` with arguments (already shell-quoted) and collects its exit code and output.
Result sear(const std::string& args) {
  static int n = 0;
  const fs::path dir = fs::temp_directory_path() / ("sear_cli_" + std::to_string(getpid()) + "_" + std::to_string(++n));
  fs::create_directories(dir);
  const std::string cmd = std::string(SEAR_BINARY) + " " + args + " >" + (dir / "out").string() + " 2>" +
                          (dir / "err").string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read(dir / "out"), read(dir / "err")};
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sear_cli_" + std::to_string(getpid()) + "_" + name);
  fs::remove_all(dir);
  return dir;
}

TEST(SearCli, DefaultProjectRunsAreByteIdentical) {
  const fs::path a = fresh_dir("det_a"), b = fresh_dir("det_b");
  ASSERT_EQ(sear("run --quiet --duration 12 -o " + a.string()).exit_code, 0);
  ASSERT_EQ(sear("run --quiet --duration 12 -o " + b.string()).exit_code, 0);
  const std::string trace = read(a / "trace_rover.csv");
  // 12 s at the default project's 50 rows per second, plus the header and the row at t = 0.
  EXPECT_EQ(std::count(trace.begin(), trace.end(), '\n'), 12 * 50 + 2);
  EXPECT_EQ(trace, read(b / "trace_rover.csv"));
  auto ja = nlohmann::json::parse(read(a / "summary.json"));
  auto jb = nlohmann::json::parse(read(b / "summary.json"));
  for (auto* j : {&ja, &jb}) {
    j->erase("wall_time_s");  // the only fields that depend on the host
    j->erase("real_time_factor");
    j->erase("step_wall_us");
  }
  EXPECT_EQ(ja, jb);
  EXPECT_EQ(ja["status"], "completed");
  EXPECT_DOUBLE_EQ(ja["sim_time_s"].get<double>(), 12.0);
  EXPECT_EQ(ja["steps"], 12000);
  // Its firmware said the same, at the same sim times, on the console and on every pin.
  for (const char* file : {"rover.main.console.log", "rover.main.pins.vcd", "rover.main.uart0.log"}) {
    EXPECT_FALSE(read(a / file).empty()) << file;
    EXPECT_EQ(read(a / file), read(b / file)) << file;
  }
  EXPECT_GT(ja["robots"][0]["distance_m"].get<double>(), 3.0);
}

TEST(SearCli, SummaryDistanceMatchesTheTrace) {
  const fs::path out = fresh_dir("distance");
  // The rover waits for its first GPS fix (5 s) before it drives.
  ASSERT_EQ(sear("run --quiet --duration 9 --trace-rate 1000 -o " + out.string()).exit_code, 0);
  std::istringstream rows(read(out / "trace_rover.csv"));
  std::string line;
  std::getline(rows, line);
  double path = 0, px = 0, py = 0;
  bool first = true;
  while (std::getline(rows, line)) {
    double t, x, y;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &t, &x, &y), 3);
    if (!first) path += std::hypot(x - px, y - py);
    px = x, py = y, first = false;
  }
  const auto summary = nlohmann::json::parse(read(out / "summary.json"));
  // A trace row every step: the same path, up to the trace's 1 um rounding per row.
  EXPECT_NEAR(summary["robots"][0]["distance_m"].get<double>(), path, 5e-3);
  EXPECT_GT(path, 2.0);
}

TEST(SearCli, CheckListsEveryErrorAndFails) {
  const fs::path dir = fresh_dir("check");
  fs::create_directories(dir);
  std::ofstream(dir / "project.xml") << R"(<project>
  <world>
    <boxx pos="1 1"/>
    <tree pos="2 2" trunk_radius="-1"/>
  </world>
  <robot file=")" << SEAR_ASSET_DIR << R"(/robots/rover.xml" colour="red"/>
</project>
)";
  const Result r = sear("check " + dir.string());  // a folder means its project.xml
  EXPECT_EQ(r.exit_code, 1);
  const std::string file = (dir / "project.xml").string();
  EXPECT_NE(r.err.find(file + ":3: error: unknown element <boxx> in <world> (did you mean 'box'?)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file + ":4: error: <tree> attribute 'trunk_radius': -1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file + ":6: error: unknown attribute 'colour' on <robot>"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file + ": 3 errors"), std::string::npos) << r.err;
  EXPECT_EQ(sear("run " + dir.string()).exit_code, 1);
}

// Issue 22: a motor on a pin with no PWM is refused before the run, said once, at its line; a
// sensor 15 m from a 30 cm rover is a warning at its line (both from the loader, for check and run).
TEST(SearCli, CheckRefusesAMotorWithNoPwmAndWarnsOfAFarSensor) {
  const fs::path dir = fresh_dir("plausible");
  fs::create_directories(dir);
  std::ofstream(dir / "main.c") << "int main(void) { return 0; }\n";
  std::ofstream(dir / "project.xml") << R"(<project>
  <world step="0.001"/>
  <robot file=")" << SEAR_ASSET_DIR << R"(/robots/rover.xml">
    <mcu name="main">
      <firmware sources="main.c"/>
      <motor name="left" pwm="30" dir="12"/>
      <gp2d12 name="ir" adc="0" pos="15 0 2"/>
    </mcu>
  </robot>
</project>
)";
  const std::string file = (dir / "project.xml").string();
  const std::string pwm = file + ":6: error: robot 'rover': mcu 'main': motor 'left' has pwm=\"30\", a pin with no "
                                 "PWM on the ATmega2560; its PWM pins are 2..13 and 44..46\n";
  const std::string far = file + ":7: warning: robot 'rover': <gp2d12> 'ir' at pos=\"15 0 2\" is 15.1 m from the "
                                 "robot's origin, while the robot itself reaches 0.177 m from it";
  const auto times = [](const std::string& text, const std::string& part) {
    std::size_t n = 0;
    for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
    return n;
  };
  for (const std::string& command : {"check " + dir.string(), "run " + dir.string() + " -o " + (dir / "out").string()}) {
    const Result r = sear(command);
    EXPECT_EQ(r.exit_code, 1) << command << r.err;
    EXPECT_EQ(times(r.err, pwm), 1u) << command << r.err;
    EXPECT_EQ(times(r.err, far), 1u) << command << r.err;
  }
}

TEST(SearCli, CheckFindsEverythingPlacedOffTheTerrain) {
  const fs::path dir = fresh_dir("off_terrain");
  fs::create_directories(dir);
  std::ofstream(dir / "project.xml") << R"(<project>
  <world>
    <terrain type="heightmap" image=")" << SEAR_ASSET_DIR << R"(/heightmaps/hills.png" size="40 40"/>
    <tree name="lost_oak" pos="0 -30"/>
  </world>
  <robot file=")" << SEAR_ASSET_DIR << R"(/robots/rover.xml"><pose x="25" y="0"/></robot>
</project>
)";
  const Result r = sear("check " + dir.string());
  EXPECT_EQ(r.exit_code, 1);
  // The 40 m map ends 20 m from the origin: both are beyond it, and both are reported.
  const std::string file = (dir / "project.xml").string();
  EXPECT_NE(r.err.find(file + ":4: error: obstacle 'lost_oak' has no terrain under it"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file + ":6: error: robot 'rover' starts at (25.00, 0.00) m, where there is no terrain"),
            std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file + ": 2 errors\n"), std::string::npos) << r.err;
  EXPECT_EQ(sear("run " + dir.string() + " -o " + (dir / "out").string()).exit_code, 1);
}

TEST(SearCli, CheckAcceptsTheBundledProject) {
  const Result r = sear("check");
  EXPECT_NE(r.exit_code, 0);  // the project argument is required
  const Result ok = sear(std::string("check ") + SEAR_ASSET_DIR + "/projects/default.xml");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("ok (1 robot"), std::string::npos);
}

TEST(SearCli, BadNumbersOnTheCommandLineAreRefused) {
  // CLI11's ValidationError (105): a wrong command line, as docs/cli.md says, and no run starts.
  const fs::path out = fresh_dir("bad_numbers");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--duration nan", "--duration: expected a number of seconds > 0 and <= 1e7, got 'nan'"},
      {"--duration inf", "--duration: expected a number of seconds > 0 and <= 1e7, got 'inf'"},
      {"--duration -1", "--duration: expected a number of seconds > 0 and <= 1e7, got '-1'"},
      {"--duration 0", "--duration: expected a number of seconds > 0 and <= 1e7, got '0'"},
      {"--duration 2e7", "--duration: expected a number of seconds > 0 and <= 1e7, got '2e7'"},
      {"--hang-timeout nan", "--hang-timeout: expected a number of seconds 0.01..3600, got 'nan'"},
      {"--hang-timeout inf", "--hang-timeout: expected a number of seconds 0.01..3600, got 'inf'"},
      {"--hang-timeout -5", "--hang-timeout: expected a number of seconds 0.01..3600, got '-5'"},
      {"--trace-rate 0", "--trace-rate: expected a rate of 0.01..1e6 Hz, got '0'"},
      {"--trace-rate -50", "--trace-rate: expected a rate of 0.01..1e6 Hz, got '-50'"},
      {"--trace-rate nan", "--trace-rate: expected a rate of 0.01..1e6 Hz, got 'nan'"},
      {"--seed -1", "--seed: expected a whole number 0..18446744073709551615, got '-1'"},
      {"--seed 18446744073709551616", "--seed: expected a whole number 0..18446744073709551615, got '18446744073709551616'"},
      {"--seed 1.5", "--seed: expected a whole number 0..18446744073709551615, got '1.5'"},
  };
  for (const auto& [args, message] : cases) {
    const Result r = sear("run " + args + " -o " + out.string());
    EXPECT_EQ(r.exit_code, 105) << args << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
}

// A project without firmware, so that a run needs no compiler: the bundled rover, scripted.
fs::path scripted_project(const std::string& name) {
  const fs::path dir = fresh_dir(name);
  fs::create_directories(dir);
  std::ofstream(dir / "project.xml") << "<project name=\"scripted\">\n  <world/>\n  <robot file=\"" << SEAR_ASSET_DIR
                                     << "/robots/rover.xml\"/>\n</project>\n";
  return dir;
}

TEST(SearCli, TheLargestSeedIsTaken) {
  const fs::path dir = scripted_project("largest_seed");
  const Result r = sear("run " + dir.string() + " --quiet --duration 0.05 --seed 18446744073709551615 -o " +
                        (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto summary = nlohmann::json::parse(read(dir / "out" / "summary.json"));
  EXPECT_EQ(summary["seed"].get<std::uint64_t>(), 18446744073709551615ull);
}

TEST(SearCli, CheckRefusesALatin1ProjectAndAFirmwareThatCannotRun) {
  const fs::path dir = fresh_dir("latin1");
  fs::create_directories(dir / "src");
  std::ofstream(dir / "plain") << "not a program";
  fs::permissions(dir / "plain", fs::perms::owner_read | fs::perms::owner_write);
  std::ofstream(dir / "project.xml") << "<project name=\"caf\xE9\">\n  <world/>\n</project>\n";
  const std::string file = (dir / "project.xml").string();
  Result r = sear("check " + dir.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(file + ":1: error: the file is not valid UTF-8 (byte 0xE9 at column 19)"), std::string::npos)
      << r.err;
  EXPECT_EQ(sear("run " + dir.string() + " -o " + (dir / "out").string()).exit_code, 1);
  EXPECT_FALSE(fs::exists(dir / "out" / "summary.json"));

  std::ofstream(dir / "project.xml") << R"(<project>
  <world/>
  <robot file=")" << SEAR_ASSET_DIR << R"(/robots/rover.xml">
    <mcu name="main"><firmware executable="plain"/></mcu>
    <mcu name="second"><firmware sources="src"/></mcu>
  </robot>
</project>
)";
  r = sear("check " + dir.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(file + ":4: error: <firmware> firmware executable 'plain' is not executable"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find(file + ":5: error: <firmware> firmware source 'src' is a folder, expected a file"),
            std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file + ": 2 errors"), std::string::npos) << r.err;
}

TEST(SearCli, CheckPrintsAHundredErrorsAndACount) {
  const fs::path dir = fresh_dir("many_errors");
  fs::create_directories(dir);
  {
    std::ofstream xml(dir / "project.xml");
    xml << "<project>\n  <world>\n";
    for (int i = 0; i < 100000; ++i) xml << "    <tree trunk_radius=\"nan\"/>\n";
    xml << "  </world>\n</project>\n";
  }
  const Result r = sear("check " + dir.string());
  EXPECT_EQ(r.exit_code, 1);
  const std::string file = (dir / "project.xml").string();
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 102) << r.err.substr(0, 2000);
  EXPECT_NE(r.err.find(file + ":102: error: <tree> attribute 'trunk_radius': expected a number (m), got 'nan'\n"
                              "... and 99900 more errors\n" + file + ": 100000 errors\n"),
            std::string::npos) << r.err.substr(r.err.size() > 2000 ? r.err.size() - 2000 : 0);
}

TEST(SearCli, HelpNamesEveryRunOption) {
  const Result r = sear("run --help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* option : {"--duration", "--seed", "--out", "--trace-rate", "--quiet"})
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
}

TEST(SearCli, InterruptedRunKeepsCompleteFiles) {
  const fs::path out = fresh_dir("interrupt");
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const std::string dir = out.string();
    const int devnull = ::open("/dev/null", O_WRONLY);
    dup2(devnull, 1);
    execl(SEAR_BINARY, "sear", "run", "--quiet", "--duration", "100000", "-o", dir.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait until it has written some trace, then interrupt it as Ctrl-C would.
  for (int i = 0; i < 200 && (!fs::exists(out / "trace_rover.csv") || fs::file_size(out / "trace_rover.csv") < 100000); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  kill(child, SIGINT);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const auto summary = nlohmann::json::parse(read(out / "summary.json"));
  EXPECT_EQ(summary["status"], "interrupted");
  const std::string trace = read(out / "trace_rover.csv");
  ASSERT_FALSE(trace.empty());
  EXPECT_EQ(trace.back(), '\n');  // the last row is whole
  const double sim_time = summary["sim_time_s"].get<double>();
  const auto last_row = trace.substr(trace.rfind('\n', trace.size() - 2) + 1);
  EXPECT_NEAR(std::stod(last_row), sim_time, 0.02 + 1e-9);  // the trace reaches where the run stopped
}

}  // namespace
