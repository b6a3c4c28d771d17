// The `sear` subcommands and the options they take.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sear {

struct RunOptions {
  std::string project;                   // file, or a folder holding project.xml; empty: the bundled default
  std::optional<double> duration_s;      // overrides the project's <run duration>
  std::optional<std::uint64_t> seed;     // overrides the project's <run seed>
  std::optional<double> trace_rate_hz;   // overrides the project's <run trace_rate>
  std::string engine;                    // "native" or "avr" for every MCU; empty: each <mcu engine>
  bool cross_check = false;              // run on both engines and report where they part (cross_check.cpp)
  bool eeprom_copies = false;            // kept EEPROMs start from their files but live in the run's folder
  std::string out_dir;                   // empty: sear-out/SCENARIO (sear/run_folder.hpp)
  bool quiet = false;
  double hang_timeout_s = 5;  // host seconds a firmware may go without progress
  bool keep_going = false;    // a stopped firmware does not end the run
  double max_file_mb = 256;   // the most any one output file of the run may hold, in MiB
  bool uart_frames = false;   // pins.vcd draws each UART byte's frame bit by bit (--uart-frames)
  std::vector<std::string> ptys;  // UART devices ("robot.mcu.device") given to the host as pseudo-terminals
  std::vector<std::string> cans;  // CAN buses bridged to SocketCAN ("bus=interface")
  std::optional<double> realtime;  // run no faster than this many times real time
  std::optional<std::string> lcm_url;  // publish on LCM at this URL (--lcm)
  std::string lcm_log;                 // write what is published into this LCM event log (--lcm-log)
  double lcm_rate_hz = 50;             // POSE and CLOCK messages per simulated second
  double lcm_batch_rate_hz = 10;       // READING, TX/RX and CAN batches per simulated second
  std::int64_t lcm_lockstep = 0;       // wait for the controller's DRIVE every this many steps; 0: never
  double lcm_timeout_s = 5;            // host seconds a lockstep controller may stay silent
  std::string junit;                   // a JUnit report of the expectations, written here
  std::optional<double> timeout_s;     // sim seconds after which pending expectations fail
  bool go_on = false;                  // run to the end even once every expectation is decided
  bool plots = true;                   // draw OUT/plot_*.png once the run is over (also off with SEAR_NO_PLOTS=1)
  bool wait_plots = false;             // exit only once the plots are drawn (else they are drawn in the background)
  // The browser viewer (`sear run --view`, `sear view`) and the run's replay file.
  bool view = false;                    // serve the viewer while the run goes on
  std::string view_bind = "127.0.0.1";  // its address (--bind)
  int view_port = 8080;                 // its port (--port); 0: any free one
  bool view_wait_start = false;         // `sear view`: hold at t = 0 until the page's Start
  bool view_keep_serving = false;       // `sear view`, `run --view-keep`: serve the final state until Ctrl-C
  double view_wait_page_s = 0;          // `run --view-wait S`: hold at t = 0 until a page connects
  std::string replay;                   // write the run's replay here (--replay)
  double replay_rate_hz = 20;           // its frames per simulated second (--replay-rate)
  std::vector<std::string> urdf_packages;  // --package NAME=DIR for every URDF robot (urdf_options.hpp)
  std::vector<std::string> urdf_args;      // --arg NAME=VALUE
};

// `sear run`'s exit code when an expectation failed (1: bad input, 3: an MCU stopped, 4: physics
// failed, 6: an LCM controller went away, 128 + signal: interrupted).
inline constexpr int kExpectationFailedExitCode = 5;

// A project argument as the user typed it -> the project file to load.
std::string resolve_project_path(const std::string& argument);

// A sketch folder without project.xml (or a .ino): the default Arduino robot's project for it,
// written under the firmware cache; nullopt for anything else (sketch_project.cpp).
std::optional<std::string> sketch_default_project(const std::string& argument);

int run_command(const RunOptions& options);
// `sear run --cross-check`: the run on the native engine, then on the AVR engine (OUT/native,
// OUT/avr), and OUT/cross_check.json naming each difference and its likely cause; exit code 5
// when they part.
int cross_check_command(const RunOptions& options);
// `sear view --replay FILE`: the viewer playing FILE back; no simulation runs.
int view_replay_command(const std::string& file, const std::string& bind, int port);

struct ProjectDesc;
struct SourceRef;
// Builds the firmware of every MCU that names C sources (cached) and records the executable in its
// description. Throws FirmwareBuildError with the compiler's messages.
void build_project_firmware(ProjectDesc& project, bool quiet);
// `packages` and `args`: the --package and --arg values (urdf_options.hpp).
int check_command(const std::string& project, const std::vector<std::string>& packages = {},
                  const std::vector<std::string>& args = {});
// Lists the device kinds of the table, with their wiring and parameters: as text, as a JSON list
// (one object per kind, for tools) or as docs/project.md's Markdown reference.
enum class SensorsFormat { Text, Json, Markdown };
int sensors_command(SensorsFormat format);
// Prints each URDF robot's import warnings ("file:line: warning: ...") on stderr, and returns them.
std::vector<std::pair<SourceRef, std::string>> print_import_warnings(const ProjectDesc& project);
// Prints the world-building errors in `text` (one per line), the first hundred and a count, as
// the loader's; returns how many there were.
std::size_t print_world_errors(const std::string& path, const std::string& text);

// `sear test DIR`: every scenario under DIR, over seeds, in parallel or sharded, one JUnit report.
struct TestOptions {
  std::string dir;
  std::size_t jobs = 1;                // runs at once (the default is set with the option)
  std::string seeds;                   // "A..B": each scenario once per seed; empty: once, with its own
  std::string shard;                   // "K/N": only the cases i with i % N == K - 1
  std::string junit;                   // the suite's JUnit report, written here
  std::string out_dir = "sear-test-out";
  std::optional<double> timeout_s;     // passed on to each run
  std::vector<std::string> merge;      // OUT IN...: join shard reports instead of running
  std::vector<std::string> urdf_packages, urdf_args;  // --package and --arg, passed on to each run
};
}  // namespace sear
namespace CLI {
class App;
}  // namespace CLI
namespace sear {
// Declares `sear test` and its options on `app`, filling `options` when parsed.
CLI::App* add_test_subcommand(CLI::App& app, TestOptions& options);
int test_command(const TestOptions& options);

// `sear new DIR`: a project from assets/templates/TEMPLATE, into a new or empty folder.
struct NewOptions {
  std::string dir;
  std::string template_name = "avoider";
  std::string name;  // empty: the folder's name
};
std::vector<std::string> project_templates();  // the template names, sorted
int new_command(const NewOptions& options);

}  // namespace sear
