// `sear`: runs and checks SEAR projects.
#include <CLI/CLI.hpp>

#include "scene/description.hpp"
#include "sear/commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"SEAR: unmodified microcontroller firmware driving a physically simulated robot."};
  app.require_subcommand(1);

  sear::RunOptions run;
  CLI::App* run_cmd = app.add_subcommand("run", "Run a project headless and write its trace and summary");
  run_cmd->add_option("project", run.project,
                      "Project file, or a folder holding project.xml (default: the bundled default project)");
  run_cmd->add_option("-d,--duration", run.duration_s, "Simulated seconds to run (default: the project's <run duration>)")
      ->check(CLI::PositiveNumber & CLI::Range(0.0, sear::kMaxTime_s));
  run_cmd->add_option("-s,--seed", run.seed, "Random seed (default: the project's <run seed>)");
  run_cmd->add_option("-o,--out", run.out_dir, "Output folder for traces and the summary")->capture_default_str();
  run_cmd->add_option("-r,--trace-rate", run.trace_rate_hz,
                      "Trace rows per simulated second, rounded to whole steps (default: the project's)")
      ->check(CLI::Range(sear::kMinTraceRate_hz, sear::kMaxTraceRate_hz));
  run_cmd->add_flag("-q,--quiet", run.quiet, "Print nothing but errors");
  run_cmd->add_option("--hang-timeout", run.hang_timeout_s,
                      "Host seconds a firmware may go without a HAL call before it is reported as hung and stopped")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 3600.0));
  run_cmd->add_flag("--keep-going", run.keep_going,
                    "When a firmware crashes, exits or hangs, go on without that MCU (the run still fails at the end)");

  std::string check_project;
  CLI::App* check_cmd = app.add_subcommand("check", "Validate a project without running it; lists every error found");
  check_cmd->add_option("project", check_project, "Project file, or a folder holding project.xml")->required();

  CLI11_PARSE(app, argc, argv);
  if (run_cmd->parsed()) return sear::run_command(run);
  return sear::check_command(check_project);
}
