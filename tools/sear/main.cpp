// `sear`: runs and checks SEAR projects.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "scene/description.hpp"
#include "lcm/lcm_channels.hpp"
#include "sear/commands.hpp"
#include "sear/urdf_options.hpp"

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
                      "Project file, a folder holding project.xml, or a scenario file naming a project (default: the bundled "
                      "default project)");
  run_cmd->add_option("-d,--duration", run.duration_s, "Simulated seconds to run (default: the project's <run duration>)")
      ->check(finite_number(0, sear::kMaxTime_s, true, "a number of seconds > 0 and <= 1e7"));
  run_cmd->add_option("-s,--seed", run.seed, "Random seed (default: the project's <run seed>)")->check(seed_number());
  run_cmd->add_option("-o,--out", run.out_dir,
                      "Output folder for traces and the summary, emptied of an earlier run's files first (default: "
                      "sear-out/NAME, NAME the scenario's or project's; sear-out/latest links to the last)");
  run_cmd->add_option("-r,--trace-rate", run.trace_rate_hz,
                      "Trace rows per simulated second, rounded to whole steps (default: the project's)")
      ->check(finite_number(sear::kMinTraceRate_hz, sear::kMaxTraceRate_hz, false, "a rate of 0.01..1e6 Hz"));
  run_cmd->add_flag("-q,--quiet", run.quiet, "Print nothing but errors");
  sear::add_urdf_options(run_cmd, run.urdf_packages, run.urdf_args);
  run_cmd->add_option("--engine", run.engine,
                      "Run every MCU on this engine: native (the firmware as a host process) or avr (its "
                      "ATmega2560 image, instruction by instruction on libsimavr); default: each <mcu engine>")
      ->check(CLI::IsMember({"native", "avr"}));
  run_cmd->add_flag("--cross-check", run.cross_check,
                    "Run on both engines (OUT/native, OUT/avr) with the same scenario and seed, and report where "
                    "they part (OUT/cross_check.json); exit code 5 when they do");
  run_cmd->add_option("--hang-timeout", run.hang_timeout_s,
                      "Host seconds a firmware may go without a HAL call before it is reported as hung and stopped")
      ->capture_default_str()
      ->check(finite_number(0.01, 3600.0, false, "a number of seconds 0.01..3600"));
  run_cmd->add_option("--max-file-mb", run.max_file_mb,
                      "The most any one output file may hold, in MiB; a file at its limit ends with a note saying so")
      ->capture_default_str()
      ->check(finite_number(0.001, 1048576.0, false, "a size in MiB 0.001..1048576"));
  run_cmd->add_flag("--uart-frames", run.uart_frames,
                    "Draw the UART traffic in the waveforms: each byte's frame, bit by bit, on its USART pins in "
                    "OUT/ROBOT.MCU.pins.vcd, for a logic analyser's UART decoder, and its value in values.vcd (without it "
                    "those pins show x once their port has begun, and the bytes are in the UART logs only)");
  run_cmd->add_flag("--keep-going", run.keep_going,
                    "When a firmware crashes, exits or hangs, go on without that MCU (the run still fails at the end)");
  run_cmd->add_option("--junit", run.junit,
                      "Write the expectations' verdicts as a JUnit XML report (one test case each, the console logs "
                      "attached); exit code 5 when one failed")
      ->type_name("FILE");
  run_cmd->add_option("--timeout", run.timeout_s,
                      "Sim seconds after which expectations still pending fail (default: the scenario's timeout); "
                      "with expectations the run lasts this long unless --duration says otherwise")
      ->check(finite_number(0, sear::kMaxTime_s, true, "a number of seconds > 0 and <= 1e7"));
  run_cmd->add_flag("--go-on", run.go_on, "Run to the end even once every expectation is decided");
  run_cmd->add_flag("!--no-plots", run.plots,
                    "Do not draw the plots (OUT/plot_*.png) after the run; SEAR_NO_PLOTS=1 in the environment does the same");
  run_cmd->add_flag("--wait-plots", run.wait_plots,
                    "Exit only once the plots are drawn (by default they are drawn in the background after the run)");
  run_cmd->add_option("--pty", run.ptys,
                      "Give a UART device (robot.mcu.device, e.g. rover.main.gps) to host programs as a pseudo-terminal "
                      "instead of its MCU port; its path is printed and linked as OUT/robot.mcu.device.pty")
      ->type_name("DEVICE");
  run_cmd->add_option("--can", run.cans,
                      "Bridge the project's CAN bus to the SocketCAN interface IFACE (vcan0, can0), both ways; "
                      "BUS=IFACE picks one of several <can_bus>")
      ->type_name("[BUS=]IFACE");
  run_cmd->add_option("--realtime", run.realtime,
                      "Run no faster than FACTOR times real time (default 1), for host programs with timeouts")
      ->expected(0, 1)
      ->default_str("1")
      ->check(finite_number(0.001, 1e6, false, "a factor 0.001..1e6"));

  run_cmd->add_option("--lcm", run.lcm_url,
                      "Publish the run on LCM and take DRIVE and CONTROL messages (channels: see docs/bridges.md); "
                      "a CONTROL reset starts the run over at t = 0, rewriting its output files")
      ->expected(0, 1)
      ->default_str(sear::kLcmDefaultUrl)
      ->type_name("URL")
      // Its value is optional, so `--lcm project.xml` would take the project for the URL.
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            if (text.find("://") != std::string::npos) return {};
            return fmt::format("'{}' is not an LCM URL (like {}); a project after --lcm is read as its URL: "
                               "put --lcm after the project, or write --lcm=URL",
                               text, sear::kLcmDefaultUrl);
          },
          "URL", "LCM_URL"));
  run_cmd->add_option("--lcm-log", run.lcm_log,
                      "Write every message the run publishes into this LCM event log (lcm-logplayer replays it), "
                      "with or without --lcm")
      ->type_name("FILE");
  run_cmd->add_option("--lcm-rate", run.lcm_rate_hz,
                      "POSE and CLOCK messages per simulated second; DRIVE and CONTROL are taken as often "
                      "(OUTPUTS go out when a pin changed)")
      ->capture_default_str()
      ->check(finite_number(0.01, 1e6, false, "a rate of 0.01..1e6 Hz"));
  run_cmd->add_option("--lcm-batch-rate", run.lcm_batch_rate_hz,
                      "READING, TX/RX and CAN messages per simulated second, each carrying every sample, byte or "
                      "frame since the last with its own time")
      ->capture_default_str()
      ->check(finite_number(0.01, 1e6, false, "a rate of 0.01..1e6 Hz"));
  run_cmd->add_option("--lcm-lockstep", run.lcm_lockstep,
                      "Every N steps publish the CLOCK and wait for the DRIVE answering it for each robot without an MCU")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{INT32_MAX}))
      ->type_name("N");
  run_cmd->add_option("--lcm-timeout", run.lcm_timeout_s,
                      "Host seconds a lockstep controller may stay silent before the run ends (exit code 6)")
      ->capture_default_str()
      ->check(finite_number(0.01, 86400.0, false, "a number of seconds 0.01..86400"));

  // The browser viewer: live beside a run (`run --view`, `view`), or a replay file played back.
  CLI::Option* run_view = run_cmd->add_flag(
      "--view", run.view, "Serve the browser viewer while the run goes on; it stops with the run (`sear view` stays)");
  const auto add_view_address = [](CLI::App* cmd, sear::RunOptions& options) {
    cmd->add_option("--bind", options.view_bind,
                    "The viewer's IPv4 address; 0.0.0.0 opens it to other machines, and whoever reaches it can "
                    "pause, reset and drive the run")
        ->capture_default_str()
        ->type_name("ADDR");
    return cmd->add_option("--port", options.view_port, "The viewer's port; 0: any free one (the address is printed)")
        ->capture_default_str()
        ->check(CLI::Range(0, 65535));
  };
  add_view_address(run_cmd, run)->needs(run_view);
  run_cmd->get_option("--bind")->needs(run_view);
  // A short run ends before a browser can connect: hold it at t = 0 for the first page, and keep
  // its end on show, when asked.
  run_cmd
      ->add_option("--view-wait", run.view_wait_page_s,
                   "Hold at t = 0 until a page connects, for at most S seconds of wall time (0: do not wait)")
      ->type_name("S")
      ->needs(run_view)
      ->check(finite_number(0, 86400, false, "0..86400 seconds"));
  run_cmd->add_flag("--view-keep", run.view_keep_serving, "After the run, serve its final state until Ctrl-C")
      ->needs(run_view);
  run_cmd->add_option("--replay", run.replay,
                      "Write the run's replay into FILE (gzip, the viewer's messages a line each) for `sear view --replay FILE`")
      ->type_name("FILE");
  run_cmd->add_option("--replay-rate", run.replay_rate_hz, "Replay frames per simulated second")
      ->capture_default_str()
      ->check(finite_number(0.1, 1000.0, false, "a rate of 0.1..1000 Hz"));

  sear::RunOptions view;
  view.view = view.view_keep_serving = true;
  bool view_start = false;
  std::string view_replay;
  CLI::App* view_cmd = app.add_subcommand(
      "view", "Run a project in the browser viewer: it waits at t = 0 for Start (Space), runs at real time, and stays "
              "until Ctrl-C; or play a replay file back");
  view_cmd->add_option("project", view.project, "Project file, folder or scenario file (default: the bundled default project)");
  add_view_address(view_cmd, view);
  view_cmd->add_flag("--start", view_start, "Start at once instead of waiting for Start");
  view_cmd->add_option("--replay", view_replay, "Play FILE (written by `sear run --replay FILE`) back; no simulation runs")
      ->type_name("FILE");
  view_cmd->add_option("--realtime", view.realtime, "Speed, in times real time, until the page changes it (default 1)")
      ->check(finite_number(0.001, 1e6, false, "a factor 0.001..1e6"));
  view_cmd->add_option("-d,--duration", view.duration_s, "Simulated seconds to run (default: the project's)")
      ->check(finite_number(0, sear::kMaxTime_s, true, "a number of seconds > 0 and <= 1e7"));
  view_cmd->add_option("-s,--seed", view.seed, "Random seed (default: the project's)")->check(seed_number());
  view_cmd->add_option("-o,--out", view.out_dir,
                       "Output folder for traces and the summary, emptied of an earlier run's files first (default: "
                       "sear-out/NAME.view)");
  view_cmd->add_option("-r,--trace-rate", view.trace_rate_hz, "Trace rows per simulated second (default: the project's)")
      ->check(finite_number(sear::kMinTraceRate_hz, sear::kMaxTraceRate_hz, false, "a rate of 0.01..1e6 Hz"));
  view_cmd->add_flag("-q,--quiet", view.quiet, "Print nothing but errors (and the viewer's address)");
  view_cmd->add_flag("--keep-going", view.keep_going, "When a firmware stops, go on without that MCU");
  view_cmd->add_option("--pty", view.ptys, "Give a UART device to host programs as a pseudo-terminal (as `sear run`)")
      ->type_name("DEVICE");
  view_cmd->add_option("--can", view.cans, "Bridge a CAN bus to SocketCAN (as `sear run`)")->type_name("[BUS=]IFACE");
  view_cmd->add_flag("!--no-plots", view.plots, "Do not draw the plots after the run");
  sear::add_urdf_options(view_cmd, view.urdf_packages, view.urdf_args);

  std::string check_project;
  CLI::App* check_cmd = app.add_subcommand("check", "Validate a project without running it; lists every error found");
  check_cmd->add_option("project", check_project, "Project file, or a folder holding project.xml")->required();
  std::vector<std::string> check_packages, check_args;
  sear::add_urdf_options(check_cmd, check_packages, check_args);

  CLI::App* sensors_cmd =
      app.add_subcommand("sensors", "List every sensor and device a project's <mcu> can hold, with its wiring and parameters");
  auto sensors_format = sear::SensorsFormat::Text;
  CLI::Option* sensors_json = sensors_cmd->add_flag_callback(
      "--json", [&] { sensors_format = sear::SensorsFormat::Json; }, "Print a JSON list, one object per kind, for tools");
  sensors_cmd
      ->add_flag_callback(
          "--markdown", [&] { sensors_format = sear::SensorsFormat::Markdown; },
          "Print the reference docs/project.md holds between its `sear sensors --markdown` markers")
      ->excludes(sensors_json);

  sear::TestOptions test;
  CLI::App* test_cmd = sear::add_test_subcommand(app, test);

  sear::NewOptions new_project;
  CLI::App* new_cmd = app.add_subcommand("new", "Write a new project (firmware, project file with expectations, CMake "
                                                "build for the simulator and the ATmega2560) into a new or empty folder");
  new_cmd->add_option("dir", new_project.dir, "The folder to write; it must not exist or be empty")->required();
  CLI::Option* new_template = new_cmd->add_option("-t,--template", new_project.template_name, "What the firmware does")
                                   ->capture_default_str()
                                   ->check(CLI::IsMember(sear::project_templates()));
  new_cmd->add_flag_callback("--arduino", [&] { new_project.template_name = "arduino"; },
                             "An Arduino sketch (DIR/DIR.ino) on the default Arduino robot: --template arduino")
      ->excludes(new_template);
  new_cmd->add_option("-n,--name", new_project.name, "The project's name (default: the folder's)");

  CLI11_PARSE(app, argc, argv);
  if (new_cmd->parsed()) return sear::new_command(new_project);
  if (test_cmd->parsed()) return sear::test_command(test);
  if (run_cmd->parsed()) return run.cross_check ? sear::cross_check_command(run) : sear::run_command(run);
  if (view_cmd->parsed()) {
    if (!view_replay.empty()) return sear::view_replay_command(view_replay, view.view_bind, view.view_port);
    view.view_wait_start = !view_start;
    if (!view.realtime) view.realtime = 1.0;  // `sear view` watches at real time unless told otherwise
    return sear::run_command(view);
  }
  if (sensors_cmd->parsed()) return sear::sensors_command(sensors_format);
  return sear::check_command(check_project, check_packages, check_args);
}
