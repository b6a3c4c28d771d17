// `sear`: runs and checks SEAR projects.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "scene/description.hpp"
#include "sear/commands.hpp"

namespace {

// A number in [lo, hi] (or (lo, hi] when `lo_exclusive`), finite. CLI11's own Range and
// PositiveNumber let NaN through (every comparison with it is false), and print their bounds with
// all of a double's digits; this one refuses nan, inf and trailing junk and says what it expects.
CLI::Validator finite_number(double lo, double hi, bool lo_exclusive, const std::string& expected) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        errno = 0;
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        const bool number = !text.empty() && end && *end == '\0' && errno != ERANGE && std::isfinite(v);
        if (number && (lo_exclusive ? v > lo : v >= lo) && v <= hi) return {};
        return fmt::format("expected {}, got '{}'", expected, text);
      },
      expected, "FINITE");
}

// A seed: a whole number 0..2^64-1 written in decimal. strtoull alone would take "-1" as 2^64-1
// and saturate past the top, so the digits are checked first and ERANGE after.
CLI::Validator seed_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const bool digits = !text.empty() && text.size() <= 20 &&
                            text.find_first_not_of("0123456789") == std::string::npos;
        errno = 0;
        if (digits) {
          (void)std::strtoull(text.c_str(), nullptr, 10);
          if (errno != ERANGE) return {};
        }
        return fmt::format("expected a whole number 0..18446744073709551615, got '{}'", text);
      },
      "0..2^64-1", "SEED");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"SEAR: unmodified microcontroller firmware driving a physically simulated robot."};
  app.require_subcommand(1);

  sear::RunOptions run;
  CLI::App* run_cmd = app.add_subcommand("run", "Run a project headless and write its trace and summary");
  run_cmd->add_option("project", run.project,
                      "Project file, or a folder holding project.xml (default: the bundled default project)");
  run_cmd->add_option("-d,--duration", run.duration_s, "Simulated seconds to run (default: the project's <run duration>)")
      ->check(finite_number(0, sear::kMaxTime_s, true, "a number of seconds > 0 and <= 1e7"));
  run_cmd->add_option("-s,--seed", run.seed, "Random seed (default: the project's <run seed>)")->check(seed_number());
  run_cmd->add_option("-o,--out", run.out_dir, "Output folder for traces and the summary")->capture_default_str();
  run_cmd->add_option("-r,--trace-rate", run.trace_rate_hz,
                      "Trace rows per simulated second, rounded to whole steps (default: the project's)")
      ->check(finite_number(sear::kMinTraceRate_hz, sear::kMaxTraceRate_hz, false, "a rate of 0.01..1e6 Hz"));
  run_cmd->add_flag("-q,--quiet", run.quiet, "Print nothing but errors");
  run_cmd->add_option("--hang-timeout", run.hang_timeout_s,
                      "Host seconds a firmware may go without a HAL call before it is reported as hung and stopped")
      ->capture_default_str()
      ->check(finite_number(0.01, 3600.0, false, "a number of seconds 0.01..3600"));
  run_cmd->add_option("--max-file-mb", run.max_file_mb,
                      "The most any one output file may hold, in MiB; a file at its limit ends with a note saying so")
      ->capture_default_str()
      ->check(finite_number(0.001, 1048576.0, false, "a size in MiB 0.001..1048576"));
  run_cmd->add_flag("--keep-going", run.keep_going,
                    "When a firmware crashes, exits or hangs, go on without that MCU (the run still fails at the end)");

  std::string check_project;
  CLI::App* check_cmd = app.add_subcommand("check", "Validate a project without running it; lists every error found");
  check_cmd->add_option("project", check_project, "Project file, or a folder holding project.xml")->required();

  CLI::App* sensors_cmd =
      app.add_subcommand("sensors", "List every sensor and device a project's <mcu> can hold, with its wiring and parameters");

  CLI11_PARSE(app, argc, argv);
  if (run_cmd->parsed()) return sear::run_command(run);
  if (sensors_cmd->parsed()) return sear::sensors_command();
  return sear::check_command(check_project);
}
