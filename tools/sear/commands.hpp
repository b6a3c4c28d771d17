// The `sear` subcommands and the options they take.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace sear {

struct RunOptions {
  std::string project;                   // file, or a folder holding project.xml; empty: the bundled default
  std::optional<double> duration_s;      // overrides the project's <run duration>
  std::optional<std::uint64_t> seed;     // overrides the project's <run seed>
  std::optional<double> trace_rate_hz;   // overrides the project's <run trace_rate>
  std::string out_dir = "sear-out";
  bool quiet = false;
  double hang_timeout_s = 5;  // host seconds a firmware may go without progress
  bool keep_going = false;    // a stopped firmware does not end the run
  double max_file_mb = 256;   // the most any one output file of the run may hold, in MiB
};

// A project argument as the user typed it -> the project file to load.
std::string resolve_project_path(const std::string& argument);

int run_command(const RunOptions& options);

struct ProjectDesc;
// Builds the firmware of every MCU that names C sources (cached) and records the executable in its
// description. Throws FirmwareBuildError with the compiler's messages.
void build_project_firmware(ProjectDesc& project, bool quiet);
int check_command(const std::string& project);
// Lists the device kinds of the table, with their wiring and parameters.
int sensors_command();
// Prints the world-building errors in `text` (one per line), the first hundred and a count, as
// the loader's; returns how many there were.
std::size_t print_world_errors(const std::string& path, const std::string& text);

}  // namespace sear
