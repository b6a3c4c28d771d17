// However a run ends (its end, Ctrl-C, SIGTERM, SIGHUP, SIGKILL, a closed stdout) no process of
// it survives, forked children included, and a stop request is honoured in every state a
// firmware can be in: spinning without HAL calls, asleep in a host call, stopped by SIGSTOP.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "firmware_run.hpp"

namespace sear::test {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

// A `sear run` started in the background, as a terminal or a CI runner starts it.
class BackgroundRun {
 public:
  BackgroundRun(const TempDir& dir, const std::string& project, const std::vector<std::string>& extra,
                const std::map<std::string, std::string>& env = {}, bool stops_blocked = false)
      : out_(dir.path() / "out") {
    const auto project_file = dir.path() / "project.xml";
    std::ofstream(project_file) << project;
    std::vector<std::string> args{SEAR_BINARY, "run", project_file.string(), "-o", out_.string(), "--hang-timeout", "60"};
    args.insert(args.end(), extra.begin(), extra.end());
    const std::string stdout_path = (dir.path() / "stdout").string(), stderr_path = (dir.path() / "stderr").string();
    pid_ = fork();
    if (pid_ == 0) {
      for (const auto& [k, v] : env) setenv(k.c_str(), v.c_str(), 1);
      if (stops_blocked) {  // as a parent that blocked them passes them on through exec
        sigset_t stops;
        sigemptyset(&stops);
        for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&stops, sig);
        sigprocmask(SIG_BLOCK, &stops, nullptr);
      }
      if (!freopen(stdout_path.c_str(), "w", stdout) || !freopen(stderr_path.c_str(), "w", stderr)) _exit(126);
      std::vector<char*> argv;
      for (auto& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
    err_path_ = stderr_path;
  }
  ~BackgroundRun() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  pid_t pid() const { return pid_; }
  const fs::path& out() const { return out_; }
  std::string err() const { return read_file(err_path_); }

  // Waits until the console log holds `text`; false after `limit`.
  bool wait_for_console(const std::string& text, std::chrono::seconds limit = 60s) const {
    const auto until = Clock::now() + limit;
    while (Clock::now() < until) {
      if (read_file(out_ / "rover.main.console.log").find(text) != std::string::npos) return true;
      std::this_thread::sleep_for(20ms);
    }
    return false;
  }
  // The exit status once it ended, or -1 if it is still running after `limit`.
  int wait_exit(std::chrono::seconds limit) {
    const auto until = Clock::now() + limit;
    while (Clock::now() < until) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return status;
      }
      std::this_thread::sleep_for(10ms);
    }
    return -1;
  }

 private:
  fs::path out_;
  std::string err_path_;
  pid_t pid_ = -1;
};

// Every process that carries a run's simulator pid in its environment: its firmware, and
// whatever the firmware forked. (The keeper, a fork of the simulator, is found by its parent.)
std::set<pid_t> processes_of_run(pid_t simulator) {
  std::set<pid_t> found;
  char wanted[64];
  std::snprintf(wanted, sizeof wanted, "SEAR_SIM_PID=%010d", static_cast<int>(simulator));
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string env = read_file(entry.path() / "environ");
    if (env.find(wanted) != std::string::npos) found.insert(static_cast<pid_t>(std::stoi(name)));
    // A zombie's environment cannot be read; it is gone as soon as its parent reaps it.
  }
  return found;
}

std::set<pid_t> children_of(pid_t parent) {
  std::set<pid_t> found;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::istringstream stat(read_file(entry.path() / "stat"));
    std::string pid, comm, state;
    int ppid = 0;
    stat >> pid >> comm >> state >> ppid;
    if (ppid == parent) found.insert(static_cast<pid_t>(std::stoi(name)));
  }
  return found;
}

bool alive(pid_t pid) {
  const std::string stat = read_file("/proc/" + std::to_string(pid) + "/stat");
  if (stat.empty()) return false;
  const auto close = stat.rfind(')');
  return close != std::string::npos && stat.size() > close + 2 && stat[close + 2] != 'Z';
}

// The firmware's pid and its forked child's, from its first console line.
std::vector<pid_t> pids_on_console(const fs::path& out) {
  std::istringstream in(read_file(out / "rover.main.console.log"));
  std::string time, word;
  std::vector<pid_t> pids;
  in >> time;
  while (in >> word) {
    if (word == "ready") break;
    if (word.find_first_not_of("0123456789") == std::string::npos) pids.push_back(std::stoi(word));
  }
  return pids;
}

// The kernel's parent-death signal and the keeper act at once; a second covers scheduling on a
// loaded two-core machine many times over.
bool all_gone(const std::vector<pid_t>& pids, std::chrono::seconds limit = 3s) {
  const auto until = Clock::now() + limit;
  while (Clock::now() < until) {
    bool any = false;
    for (const pid_t p : pids) any = any || alive(p);
    if (!any) return true;
    std::this_thread::sleep_for(20ms);
  }
  return false;
}

std::string probe_project(const char* executable, double duration_s = 100) {
  return rover_project(std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + executable +
                           "\"/>\n    </mcu>\n",
                       "", duration_s);
}

struct Ending {
  const char* name;
  const char* executable;
  int signal;
};

// Names the case in test output rather than dumping its bytes.
void PrintTo(const Ending& e, std::ostream* os) { *os << e.name; }

class KilledRun : public ::testing::TestWithParam<Ending> {};

// SIGKILL skips every clean-up of the simulator's own; SIGHUP is a closed terminal. Either way
// the firmware, its forked child and the keeper are gone within moments.
TEST_P(KilledRun, LeavesNoProcessOfTheRunBehind) {
  const Ending e = GetParam();
  TempDir dir;
  BackgroundRun run(dir, probe_project(e.executable), {"--quiet"});
  ASSERT_TRUE(run.wait_for_console("ready")) << run.err();
  std::vector<pid_t> pids = pids_on_console(run.out());
  ASSERT_FALSE(pids.empty());
  for (const pid_t p : processes_of_run(run.pid())) pids.push_back(p);
  for (const pid_t p : children_of(run.pid())) pids.push_back(p);  // firmware and keeper
  ASSERT_GE(pids.size(), 2u) << "the firmware and the keeper run beside the simulator";
  for (const pid_t p : pids) ASSERT_TRUE(alive(p)) << p;
  const pid_t simulator = run.pid();
  kill(simulator, e.signal);
  const int status = run.wait_exit(10s);
  ASSERT_NE(status, -1) << "sear did not end after " << e.name;
  EXPECT_TRUE(all_gone(pids)) << "a process of the run outlived it after " << e.name;
  EXPECT_TRUE(processes_of_run(simulator).empty());
}

INSTANTIATE_TEST_SUITE_P(EveryState, KilledRun,
                         ::testing::Values(Ending{"SIGKILL, spinning with a forked child", LIFE_FORK_PROBE, SIGKILL},
                                           Ending{"SIGKILL, asleep in a host call", LIFE_SLEEP_PROBE, SIGKILL},
                                           Ending{"SIGKILL, stopped by SIGSTOP", LIFE_STOP_PROBE, SIGKILL},
                                           Ending{"SIGHUP, spinning with a forked child", LIFE_FORK_PROBE, SIGHUP}),
                         case_name<Ending>);

class InterruptedRun : public ::testing::TestWithParam<Ending> {};

// A stop request ends the run in seconds rather than at the 60 s hang timeout, with the summary
// written, the status "interrupted" and 128 + the signal as the exit code.
TEST_P(InterruptedRun, StopsWithItsSummaryInEveryFirmwareState) {
  const Ending e = GetParam();
  TempDir dir;
  BackgroundRun run(dir, probe_project(e.executable), {"--quiet"});
  ASSERT_TRUE(run.wait_for_console("ready")) << run.err();
  std::vector<pid_t> pids = pids_on_console(run.out());
  kill(run.pid(), e.signal);
  // Honoured within a second; 10 s leaves room for a loaded machine and still fails against the
  // 60 s hang timeout a run that ignored the request would wait for.
  const int status = run.wait_exit(10s);
  ASSERT_NE(status, -1) << "sear ignored " << e.name;
  ASSERT_TRUE(WIFEXITED(status)) << run.err();
  EXPECT_EQ(WEXITSTATUS(status), 128 + e.signal) << run.err();
  const auto summary = nlohmann::json::parse(read_file(run.out() / "summary.json"));
  EXPECT_EQ(summary["status"], "interrupted");
  EXPECT_GT(summary["sim_time_s"].get<double>(), 0.0);
  EXPECT_LT(summary["sim_time_s"].get<double>(), 100.0);
  EXPECT_TRUE(all_gone(pids));
}

INSTANTIATE_TEST_SUITE_P(EveryState, InterruptedRun,
                         ::testing::Values(Ending{"SIGINT, spinning", LIFE_FORK_PROBE, SIGINT},
                                           Ending{"SIGINT, asleep in a host call", LIFE_SLEEP_PROBE, SIGINT},
                                           Ending{"SIGINT, stopped by SIGSTOP", LIFE_STOP_PROBE, SIGINT},
                                           Ending{"SIGTERM, spinning", LIFE_FORK_PROBE, SIGTERM},
                                           Ending{"SIGHUP, asleep in a host call", LIFE_SLEEP_PROBE, SIGHUP}),
                         case_name<Ending>);

// A harness whose thread blocked SIGTERM passes the block on through fork and exec; a run that
// kept it would never see the request (a `sear view` so started waited hours for its page).
TEST(RunLifecycle, AStopSignalTheParentBlockedStillStopsTheRun) {
  TempDir dir;
  BackgroundRun run(dir, probe_project(LIFE_SLEEP_PROBE), {"--quiet"}, {}, true);
  ASSERT_TRUE(run.wait_for_console("ready")) << run.err();
  kill(run.pid(), SIGTERM);
  const int status = run.wait_exit(10s);  // as InterruptedRun: a second is plenty, 60 s the hang timeout
  ASSERT_NE(status, -1) << "sear never saw the SIGTERM its parent had blocked";
  ASSERT_TRUE(WIFEXITED(status)) << run.err();
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM) << run.err();
}

// The same while a viewer waits for its first page, before the clock has moved: the run stops,
// and its MCU, which never ran, is not reported for pins it "never drove".
TEST(RunLifecycle, AViewerWaitingForItsPageStopsOnSigtermWithNoWiringVerdicts) {
  TempDir dir;
  // A sonar the probe never triggers: a run that went to its end would report its trig pin.
  const std::string project = rover_project(std::string("    <mcu name=\"main\">\n      <firmware executable=\"") +
                                                LIFE_SLEEP_PROBE + "\"/>\n      <hcsr04 name=\"sonar\" trig=\"24\" echo=\"2\" "
                                                "pos=\"0.15 0 0.05\"/>\n    </mcu>\n", "", 100);
  BackgroundRun run(dir, project, {"--view", "--port", "0", "--view-wait", "60"}, {}, true);
  bool listening = false;
  for (int i = 0; i < 1500 && !listening; ++i) {  // up to 30 s for the build and the server
    listening = run.err().find("viewer on http://") != std::string::npos;
    std::this_thread::sleep_for(20ms);
  }
  ASSERT_TRUE(listening) << run.err();
  kill(run.pid(), SIGTERM);
  const int status = run.wait_exit(10s);  // the wait polls for a stop; 60 s is its own end
  ASSERT_NE(status, -1) << "sear view went on waiting for a page after SIGTERM";
  ASSERT_TRUE(WIFEXITED(status)) << run.err();
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM) << run.err();
  EXPECT_EQ(run.err().find("wiring:"), std::string::npos) << run.err();
}

// `sear run ... | head -2`: the echo stops with the pipe; the run completes with all its files.
TEST(RunLifecycle, AClosedStandardOutputStopsTheEchoNotTheRun) {
  TempDir dir;
  std::ofstream(dir.path() / "project.xml") << probe_project(LIFE_PRINT_PROBE, 0.5);
  const std::string out = (dir.path() / "out").string();
  const std::string cmd = "bash -c '" + std::string(SEAR_BINARY) + " run " + (dir.path() / "project.xml").string() +
                          " -o " + out + " 2>" + (dir.path() / "stderr").string() +
                          " | head -2 >/dev/null; exit ${PIPESTATUS[0]}'";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << read_file(dir.path() / "stderr");
  const auto summary = nlohmann::json::parse(read_file(fs::path(out) / "summary.json"));
  EXPECT_EQ(summary["status"], "completed");
  EXPECT_DOUBLE_EQ(summary["sim_time_s"].get<double>(), 0.5);
  // A line a millisecond from about 4 ms on (its first lines' length depends on the pid it
  // prints): the console log holds every one to the end, "line 0" to at least "line 480"; the
  // very last may be cut short by the run's end, as on the wire.
  std::size_t numbered = 0;
  for (const auto& line : lines_of(read_file(fs::path(out) / "rover.main.console.log"))) {
    const auto at = line.find(" line ");
    if (at == std::string::npos || line.size() == at + 6) continue;
    EXPECT_EQ(line.substr(at + 6), std::to_string(numbered)) << line;
    ++numbered;
  }
  EXPECT_GE(numbered, 480u);
}

// A robot that drives off the terrain is reported at that moment and stopped, and so are its
// MCUs: their output ends there, and the run goes on to its end.
TEST(RunLifecycle, ARobotThatLeavesTheWorldEndsItsMcus) {
  TempDir dir;
  // An 8 m square at 0.2 m, 33 samples a side; the rover starts 2 m from its east edge.
  std::string pgm = "P5 33 33 255\n";
  pgm.append(33 * 33, static_cast<char>(255));
  dir.write("flat.pgm", pgm);
  const std::string project = std::string(
      "<project name=\"off\">\n  <run duration=\"6\" seed=\"1\" trace_rate=\"10\"/>\n"
      "  <world step=\"0.001\">\n    <terrain type=\"heightmap\" image=\"flat.pgm\" size=\"8 8\" min_height=\"0\" "
      "max_height=\"0.2\"/>\n  </world>\n  <robot file=\"") + SEAR_ASSET_DIR + "/robots/rover.xml\">\n"
      "    <pose x=\"2\" y=\"0\"/>\n    <script>\n      <motor t=\"0\" name=\"left\" duty=\"1\" dir=\"forward\"/>\n"
      "      <motor t=\"0\" name=\"right\" duty=\"1\" dir=\"forward\"/>\n    </script>\n"
      "    <mcu name=\"main\">\n      <firmware executable=\"" + TIMER_PROBE + "\"/>\n    </mcu>\n  </robot>\n</project>\n";
  const SearRun run = run_sear(dir, project, "--quiet");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("sear: robot rover left the terrain at sim time"), std::string::npos) << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_EQ(summary["status"], "completed");
  EXPECT_DOUBLE_EQ(summary["sim_time_s"].get<double>(), 6.0);
  EXPECT_TRUE(summary["mcu_stops"].empty());  // the MCU did not fail; its robot left
  ASSERT_EQ(summary["robot_events"].size(), 1u);
  const double left_s = summary["robot_events"][0]["time_s"].get<double>();
  // 2 m to the edge at the rover's top speed, 0.731 m/s, can take no less than 2.74 s; its
  // motors bring it to that speed within a few tenths of a second (their time constant, wheel
  // inertia over k, is ~10 ms, the chassis's is longer), so 0.5 s more is ample.
  EXPECT_GT(left_s, 2.0 / 0.731);
  EXPECT_LT(left_s, 2.0 / 0.731 + 0.5);
  // Pin 12 toggles every 10 ms until then; its waveform has no edge after the robot left, and
  // its last edge is within one period of it.
  long long last_edge = 0;
  for (const auto& line : lines_of(run.file("rover.main.pins.vcd")))
    if (!line.empty() && line[0] == '#') last_edge = std::stoll(line.substr(1));
  EXPECT_LE(static_cast<double>(last_edge) * 1e-9, left_s);
  EXPECT_GT(static_cast<double>(last_edge) * 1e-9, left_s - 0.0101);
}

// Ctrl-C while a firmware compiles: the compiler and everything it started are killed, no
// build is left in the cache, and the next run compiles afresh.
TEST(RunLifecycle, InterruptingACompileLeavesNoCompilerAndNoHalfBuild) {
  TempDir dir;
  const std::string marker = "31.4159";  // a sleep no other process on the machine runs
  const std::string slow_cc = dir.write("slow-cc", "#!/bin/sh\n"
                                                   "[ \"$1\" = --version ] && exec cc --version\n"
                                                   "sleep " + marker + "\n"
                                                   "exec cc \"$@\"\n");
  fs::permissions(slow_cc, fs::perms::owner_all);
  dir.write("fw/main.c", "#include <hal/hal.h>\nint main(void) { hal_init(); for (;;) delay_ms(10); }\n");
  const std::string project = rover_project("    <mcu name=\"main\">\n      <firmware sources=\"fw/main.c\"/>\n    </mcu>\n");
  const std::string cache = (dir.path() / "cache").string();
  {
    BackgroundRun run(dir, project, {"--quiet"}, {{"CC", slow_cc}, {"SEAR_CACHE_DIR", cache}});
    // The compiler is running once its sleep shows up.
    bool sleeping = false;
    for (int i = 0; i < 500 && !sleeping; ++i) {
      std::this_thread::sleep_for(20ms);
      for (const auto& entry : fs::directory_iterator("/proc"))
        if (read_file(entry.path() / "cmdline").find(marker) != std::string::npos) sleeping = true;
    }
    ASSERT_TRUE(sleeping) << run.err();
    kill(run.pid(), SIGINT);
    const int status = run.wait_exit(10s);
    ASSERT_NE(status, -1) << "sear went on compiling after Ctrl-C";
    EXPECT_EQ(WEXITSTATUS(status), 130) << run.err();
  }
  bool compiler_left = false;
  for (int i = 0; i < 100; ++i) {
    compiler_left = false;
    for (const auto& entry : fs::directory_iterator("/proc"))
      if (read_file(entry.path() / "cmdline").find(marker) != std::string::npos) compiler_left = true;
    if (!compiler_left) break;
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_FALSE(compiler_left) << "a compiler process outlived the interrupted run";
  std::size_t entries = 0;
  if (fs::exists(cache))
    for (const auto& entry : fs::directory_iterator(cache)) ++entries, ADD_FAILURE() << "left in the cache: " << entry.path();
  EXPECT_EQ(entries, 0u);
  // The next run, with the ordinary compiler, builds and completes.
  setenv("SEAR_CACHE_DIR", cache.c_str(), 1);
  const SearRun again = run_sear(dir, project, "--quiet --duration 0.1");
  unsetenv("SEAR_CACHE_DIR");
  EXPECT_EQ(again.exit_code, 0) << again.err;
}

}  // namespace
}  // namespace sear::test
