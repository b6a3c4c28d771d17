#include <fmt/format.h>
#include <signal.h>
#include <string.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "exporters/can_logs.hpp"
#include "exporters/flush_clock.hpp"
#include "exporters/mcu_capture.hpp"
#include "exporters/pin_labels.hpp"
#include "exporters/plot_runner.hpp"
#include "exporters/sensor_csv.hpp"
#include "exporters/world_json.hpp"
#include "exporters/run_summary.hpp"
#include "exporters/stdout_text.hpp"
#include "expect/expectation_checker.hpp"
#include "expect/junit_report.hpp"
#include "expect/scenario_loader.hpp"
#include "exporters/trace_csv.hpp"
#include "runtime/process_keeper.hpp"
#include "runtime/stop_request.hpp"
#include "runtime/wall_pace.hpp"
#include "runtime/while_waiting.hpp"
#include "scene/project_loader.hpp"
#include "sear/commands.hpp"
#include "sear/firmware_builder.hpp"
#include "sear/host_ports.hpp"
#include "sear/run_folder.hpp"
#include "sear/urdf_options.hpp"
#include "lcm/lcm_bridge.hpp"
#include "sear/view_command.hpp"
#include "view/replay_file.hpp"
#include "view/view_session.hpp"

namespace sear {
namespace {

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error(path + ": error: cannot write");
}

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// 128 + the signal, as shells report a process ended by it; Ctrl-C gives 130.
int interrupted_exit_code() { return 128 + stop_signal(); }

std::string interrupted_status() {
  const char* name = sigabbrev_np(stop_signal());
  return fmt::format("interrupted (SIG{})", name ? name : "?");
}

// A firmware writes its own host log, under a file-size limit set on its process; at the limit
// its writes fail, and the note is added here, by the simulator, which has no such limit.
// Returns the logs cut short.
std::vector<std::string> note_truncated_host_logs(const std::string& out_dir, const std::vector<McuCapture::Mcu>& mcus,
                                                  std::uint64_t max_file_bytes) {
  std::vector<std::string> truncated;
  for (const auto& m : mcus) {
    const std::string log = out_dir + "/" + m.id + ".host.log";
    std::error_code error;
    const std::uintmax_t size = std::filesystem::file_size(log, error);
    if (error || size < max_file_bytes) continue;
    char last = '\n';
    std::ifstream(log, std::ios::binary).seekg(-1, std::ios::end).get(last);
    std::ofstream(log, std::ios::app) << (last == '\n' ? "" : "\n") << text_truncation_note(max_file_bytes);
    truncated.push_back(log);
  }
  return truncated;
}

// Every MCU's console log as written, for the JUnit report's system-out.
std::string console_logs(const std::string& out_dir, const std::vector<McuCapture::Mcu>& mcus) {
  std::string text;
  for (const auto& m : mcus) {
    if (m.console_uart < 0) continue;
    std::ifstream in(out_dir + "/" + m.id + ".console.log", std::ios::binary);
    std::ostringstream log;
    log << in.rdbuf();
    text += fmt::format("== {} console ==\n{}", m.id, log.str());
  }
  return text;
}

// The summary's last line: where the run's files are, and which (the plots drawn among them). The
// folder was emptied before the run, so every plot in it is this run's.
std::string output_line(const std::string& out_dir, const std::vector<const BoundedFile*>& outputs) {
  std::string line = fmt::format("  output: {}/ (summary.txt, summary.json", out_dir);
  for (const auto* f : outputs) line += ", " + std::filesystem::path(f->path()).filename().string();
  std::vector<std::string> plots;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(out_dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("plot_", 0) == 0 && entry.path().extension() == ".png") plots.push_back(name);
  }
  std::sort(plots.begin(), plots.end());  // a folder lists in no set order
  for (const auto& p : plots) line += ", " + p;
  return line + ")";
}

}  // namespace

int run_command(const RunOptions& options) {
  // First of all, so that a Ctrl-C while loading or compiling is honoured as cleanly as later,
  // and so that whatever the run starts is the keeper's to kill if the simulator is killed.
  install_stop_signals();
  keeper_start();
  Diagnostics diagnostics;
  // A scenario file names its project; a project file is its own scenario (with the expectations
  // of its <expect>, if any).
  auto scenario = load_scenario(resolve_project_path(options.project), diagnostics);
  if (!scenario) {
    fmt::print(stderr, "{}", diagnostics.joined());
    return 1;
  }
  const std::string path = scenario->project_file;
  auto project = load_project(path, diagnostics, urdf_overrides(options.urdf_packages, options.urdf_args));
  fmt::print(stderr, "{}", diagnostics.warnings_joined());
  if (!project || !check_scenario(*scenario, *project, diagnostics)) {
    fmt::print(stderr, "{}", diagnostics.joined());
    return 1;
  }
  // Once, before the run starts (a reset does not load again), and into the summary.
  const auto import_warnings = print_import_warnings(*project);
  if (options.timeout_s) scenario->timeout_ns = std::llround(*options.timeout_s * 1e9);
  const bool expecting = !scenario->expectations.empty();
  // With expectations the run lasts until their timeout, unless told otherwise.
  if (expecting && scenario->timeout_ns) project->run.duration_s = static_cast<double>(*scenario->timeout_ns) * 1e-9;
  if (scenario->seed) project->run.seed = *scenario->seed;
  if (options.duration_s) project->run.duration_s = *options.duration_s;
  if (options.seed) project->run.seed = *options.seed;
  if (options.trace_rate_hz) project->run.trace_rate_hz = *options.trace_rate_hz;
  if (!options.engine.empty()) {
    // --engine puts every MCU on one engine; a firmware only one engine can run is refused.
    for (auto& robot : project->robots) {
      for (auto& mcu : robot.mcus) {
        mcu.engine = options.engine;
        const std::string id = robot.name + "." + mcu.name;
        if (mcu.engine == "avr" && !mcu.firmware_executable.empty()) {
          fmt::print(stderr, "{}:{}: error: --engine avr: mcu {} runs a host executable; the AVR engine needs its "
                             "sources or an AVR image (<firmware elf>)\n",
                     mcu.source.file, mcu.source.line, id);
          return 1;
        }
        if (mcu.engine == "native" && !mcu.firmware_elf.empty()) {
          fmt::print(stderr, "{}:{}: error: --engine native: mcu {} is an AVR image (<firmware elf>), which runs "
                             "only on the AVR engine\n",
                     mcu.source.file, mcu.source.line, id);
          return 1;
        }
      }
    }
  }
  const auto max_file_bytes = static_cast<std::uint64_t>(options.max_file_mb * 1024.0 * 1024.0);

  try {
    build_project_firmware(*project, options.quiet);
  } catch (const FirmwareBuildInterrupted& e) {
    fmt::print(stderr, "\n{}\n", e.what());
    return interrupted_exit_code();
  } catch (const FirmwareBuildError& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }

  // One run, one folder: without --out, the scenario's own under sear-out/ (a `sear view`'s apart,
  // so that a viewed run stopped half-way never replaces a completed one).
  const bool default_folder = options.out_dir.empty();
  const std::string out_dir =
      default_folder ? default_run_folder(scenario->name, options.view_keep_serving) : options.out_dir;

  // Each AVR engine keeps its report (CPU load, ISRs, top functions, stack) in the output folder;
  // the summary takes it in at the end.
  std::vector<std::pair<std::string, std::string>> avr_reports;
  for (auto& robot : project->robots) {
    for (auto& mcu : robot.mcus) {
      if (mcu.engine != "avr") continue;
      const std::string id = robot.name + "." + mcu.name;
      avr_reports.emplace_back(id, out_dir + "/" + id + ".avr.json");
      mcu.firmware_args.insert(mcu.firmware_args.begin(), {"--report", avr_reports.back().second});
    }
  }

  try {
    // An earlier run's plotter may still read the files of the folder: it finishes before they go.
    PlotFolder plot_folder(out_dir);
    if (std::filesystem::exists(std::filesystem::path(out_dir) / kRunFolderMark)) plot_folder.claim(options.quiet);
    prepare_run_folder(out_dir);
    // A cross-check runs the same project twice: each engine starts from the kept EEPROM's
    // contents, in a copy of its own in the run's folder, and the kept file stays as it was.
    if (options.eeprom_copies)
      for (auto& robot : project->robots)
        for (auto& mcu : robot.mcus) {
          if (mcu.eeprom_file.empty()) continue;
          const auto copy = std::filesystem::path(out_dir) / (robot.name + "." + mcu.name + ".eeprom");
          std::error_code error;
          if (std::filesystem::exists(mcu.eeprom_file, error))
            std::filesystem::copy_file(mcu.eeprom_file, copy, std::filesystem::copy_options::overwrite_existing);
          mcu.eeprom_file = copy.string();
        }
    if (default_folder) point_latest_at(out_dir);
    write_world_json(out_dir + "/world.json", *project);
    std::unique_ptr<LcmBridge> lcm;
    if (options.lcm_url || !options.lcm_log.empty() || options.lcm_lockstep > 0)
      lcm = std::make_unique<LcmBridge>(
          LcmOptions{options.lcm_url, options.lcm_log, options.lcm_rate_hz, options.lcm_batch_rate_hz,
                     options.lcm_lockstep, options.lcm_timeout_s});
    // The browser viewer and the replay file watch the run through one model of what it shows;
    // both, like the server's port, last across resets.
    std::unique_ptr<ViewModel> view_model;
    if (options.view || !options.replay.empty()) view_model = std::make_unique<ViewModel>(*project);
    std::unique_ptr<ViewSession> view;
    if (options.view) {
      view = std::make_unique<ViewSession>(
          *project, *view_model,
          ViewSessionOptions{view_server_options(options.view_bind, options.view_port),
                             options.realtime.value_or(0.0), options.view_wait_start,
                             options.view_wait_page_s});
      fmt::print(stderr, "sear: viewer on {}\n", view->server().url());
    }
    std::unique_ptr<ReplayFile> replay;
    if (!options.replay.empty())
      replay = std::make_unique<ReplayFile>(options.replay, *project, *view_model, options.replay_rate_hz);
    // Opened once: a host program keeps its pty or interface across a reset.
    const HostPorts host_ports(*project, options.ptys, options.cans, out_dir);
    for (const auto& port : host_ports.listing())
      if (!options.quiet)
        fmt::print(stderr, "sear: {} on the host: {}{}\n", port.name, port.path,
                   port.link.empty() ? "" : " (link " + port.link + ")");
    const char* no_plots = std::getenv("SEAR_NO_PLOTS");
    const bool plots = options.plots && !(no_plots && *no_plots && std::string(no_plots) != "0");
  start_over:  // SEAR/CONTROL's reset: the run is built again from here, at t = 0, its files rewritten
    plot_folder.claim(options.quiet);  // after `sear view`'s reset, the plotter of the run before
    Simulation sim(*project, project->run.seed);
    TraceCsv trace(out_dir, sim, max_file_bytes);
    std::vector<McuCapture::Mcu> mcus;
    for (const auto& robot : project->robots)
      for (const auto& mcu : robot.mcus)
        mcus.push_back({robot.name + "." + mcu.name, mcu.console_uart, options.uart_frames, pin_labels(mcu),
                        options.uart_frames});
    McuCapture capture(out_dir, mcus, !options.quiet, max_file_bytes);
    LockstepOptions lockstep_options;
    lockstep_options.mcu.host_serial = host_ports.serial_ends();
    lockstep_options.out_dir = out_dir;
    lockstep_options.mcu.hang_timeout_s = options.hang_timeout_s;
    lockstep_options.mcu.max_file_bytes = max_file_bytes;
    lockstep_options.keep_going = options.keep_going;
    CanLogs can_logs(out_dir, project->can_buses, max_file_bytes);
    RunTaps taps;
    if (!project->can_buses.empty()) taps.add(&can_logs);
    if (lcm) taps.add(lcm.get());
    SensorCsv sensors(out_dir, *project, 1.0 / project->run.trace_rate_hz, max_file_bytes);
    taps.add(&sensors);
    if (view_model) {
      view_model->restart();
      taps.add(view_model.get());
    }
    std::unique_ptr<ExpectationChecker> checker;
    if (expecting) {
      checker = std::make_unique<ExpectationChecker>(*scenario, *project);
      taps.add(checker.get());
    }
    lockstep_options.mcu.tap = taps.empty() ? nullptr : &taps;
    Lockstep lockstep(sim, *project, lockstep_options, capture);
    host_ports.attach_can(lockstep);
    if (lcm) lcm->start_run(sim, *project);
    if (view) view->start_run(sim);
    if (replay) replay->start_run(sim);
    const std::int64_t end_ns = std::llround(project->run.duration_s * 1e9);
    const std::int64_t trace_every =
        std::max<std::int64_t>(1, std::llround(1e9 / project->run.trace_rate_hz / static_cast<double>(sim.step_ns())));

    // The files reach the disk every FlushClock period of wall time, also while the run waits on a
    // firmware or a controller, and at once when an MCU stops or a robot leaves the world.
    const auto flush_files = [&] {
      trace.flush();
      capture.flush();
      can_logs.flush();
      sensors.flush();
    };
    FlushClock flush_clock;
    const WhileWaiting flush_while_waiting([&] {
      if (flush_clock.due()) flush_files();
    });

    const bool show_progress = !options.quiet && isatty(STDERR_FILENO);
    const auto start = Clock::now();
    WallPace pace;  // --realtime's: sim time 0 is now
    double next_progress_s = 2.0;  // short runs finish before a progress line would help

    // A step's events reach the capture's files while the firmware runs the next quantum (the
    // files wait for nothing but their events): 27 us of the reference rover's 93 us a step went
    // there while the firmware waited. They are written in the same order as before, so the files
    // are the same bytes; when the run says something, they are written first, and at its end.
    std::int64_t captured_to = 0;
    bool capture_behind = false;
    const auto catch_up = [&] {
      if (!capture_behind) return;
      capture.advance_to(captured_to);
      capture_behind = false;
    };
    const std::function<void()> alongside = catch_up;  // made once: no allocation a step

    trace.write_row(sim);
    std::int64_t steps = 0;
    std::size_t stops_reported = 0, events_reported = 0, halts_reported = 0;
    std::vector<bool> stdout_told(lockstep.mcu_count());
    bool physics_failed = false;
    bool reset = false, controller_gone = false, view_reset = false;
    while (sim.time_ns() < end_ns && !stop_requested()) {
      if (view) {
        const ViewSession::Gate gate = view->before_step(sim);
        if (gate == ViewSession::Gate::Reset) reset = view_reset = true;
        if (gate != ViewSession::Gate::Step) break;
      }
      if (lcm) {
        const LcmBridge::Gate gate = lcm->before_step();
        if (gate == LcmBridge::Gate::Reset) reset = true;
        if (gate == LcmBridge::Gate::ControllerGone) {
          if (show_progress && next_progress_s > 2.0) fmt::print(stderr, "\n");
          fmt::print(stderr, "sear: {}\n", lcm->failure());
          controller_gone = true;
        }
        if (gate != LcmBridge::Gate::Step) break;
      }
      bool go_on = false;
      try {
        go_on = lockstep.step(alongside);
      } catch (const PhysicsError& e) {
        // The world is over; what was written up to here, and the summary, still are not.
        if (show_progress && next_progress_s > 2.0) fmt::print(stderr, "\n");
        fmt::print(stderr, "sear: {}\n", e.what());
        physics_failed = true;
        break;
      }
      captured_to = sim.time_ns();  // written while the next quantum runs, or below when anything is said
      capture_behind = true;
      if (!go_on || events_reported < sim.robot_events().size() || stops_reported < lockstep.stops().size() ||
          halts_reported < lockstep.halts().size())
        catch_up();
      if (lcm) lcm->after_step();
      if (view) view->after_step(sim);
      if (replay) replay->after_step(sim);
      // A robot that left the world is reported at that moment; its MCUs end with it.
      for (; events_reported < sim.robot_events().size(); ++events_reported) {
        const RobotEvent& e = sim.robot_events()[events_reported];
        if (show_progress && next_progress_s > 2.0) fmt::print(stderr, "\n");
        fmt::print(stderr, "sear: {}\n", describe(e));
        if (e.stops_robot) lockstep.retire_robot(e.robot);
        flush_files();
      }
      for (; stops_reported < lockstep.stops().size(); ++stops_reported) {
        const McuStop& stop = lockstep.stops()[stops_reported];
        if (show_progress && next_progress_s > 2.0) fmt::print(stderr, "\n");
        fmt::print(stderr, "sear: {} (its output: {}/{}.host.log)\n", describe(stop), out_dir, stop.mcu);
        if (checker) checker->mcu_stopped(stop.mcu, stop.failure.time_ns, describe(stop));
        if (view_model) view_model->mcu_stopped(stop.mcu, describe(stop));
        flush_files();
      }
      // A halted MCU is no failure: said once, when it halts, and the run goes on.
      for (; halts_reported < lockstep.halts().size(); ++halts_reported) {
        if (show_progress && next_progress_s > 2.0) fmt::print(stderr, "\n");
        fmt::print(stderr, "sear: {}; the run goes on\n", describe(lockstep.halts()[halts_reported]));
      }
      // printf() reaches the host log only: said once, the first time, where the user looks.
      for (std::size_t i = 0; i < lockstep.mcu_count(); ++i) {
        const McuBridge& mcu = lockstep.mcu(i);
        if (stdout_told[i] || !mcu.usage().stdout_ns) continue;
        stdout_told[i] = true;
        if (show_progress && next_progress_s > 2.0) fmt::print(stderr, "\n");
        const int console = mcu.desc().console_uart;
        fmt::print(stderr,
                   "sear: mcu {} wrote to its standard output (printf, puts) by sim time {:.3f} s: that goes to "
                   "{}/{}.host.log only; {} shows text on this console\n",
                   mcu.id(), static_cast<double>(*mcu.usage().stdout_ns) * 1e-9, out_dir, mcu.id(),
                   console >= 0 ? fmt::format("uart_print({}, ...) on its console UART", console)
                                : std::string("uart_print() on the UART its console_uart names"));
      }
      if (!go_on) break;
      // Every verdict known: nothing the run could still do changes the outcome.
      if (checker && checker->decided() && !options.go_on) break;
      if (++steps % trace_every == 0) trace.write_row(sim);
      if (flush_clock.due()) flush_files();
      // Paced for host programs with timeouts of their own: never ahead of the wall clock.
      // A run that fell behind (paused over LCM, or slower than asked) goes on from where it is
      // rather than racing to catch up.
      if (options.realtime && !view) {  // the viewer paces at its own speed
        const double ahead_s = pace.ahead_s(sim.time_s(), *options.realtime);
        if (ahead_s > 0) std::this_thread::sleep_for(std::chrono::duration<double>(ahead_s));
      }
      if (show_progress && (steps & 1023) == 0 && seconds_since(start) >= next_progress_s) {
        next_progress_s += 0.5;
        const double wall = seconds_since(start);
        fmt::print(stderr, "\r  {:.1f} / {:.1f} s simulated ({:.0f}%), {:.1f}x real time ", sim.time_s(),
                   project->run.duration_s, 100.0 * sim.time_s() / project->run.duration_s, sim.time_s() / wall);
      }
    }
    catch_up();
    if (show_progress && next_progress_s > 2.0) fmt::print(stderr, "\n");
    if (reset) {
      if (replay) replay->end_segment(sim);  // what the run logged since its last frame
      fmt::print(stderr, "sear: reset by {}: the run starts over at t = 0\n", view_reset ? "the viewer" : "SEAR/CONTROL");
      goto start_over;
    }
    if (lcm) lcm->finish();
    if (replay) replay->finish(sim);
    trace.flush();
    sensors.finish();
    can_logs.flush();
    capture.finish(sim.time_ns());
    const bool interrupted = stop_requested();
    if (checker) {
      checker->finish(sim.time_ns(), interrupted);
      for (const auto& r : checker->results())
        if (r.verdict == Verdict::Failed) fmt::print(stderr, "sear: {}\n", failure_text(r));
    }
    if (!options.junit.empty()) {
      const ExpectationChecker none(*scenario, *project);
      write_junit(options.junit, {junit_suite(*scenario, project->run.seed, checker ? *checker : none, sim.time_ns(),
                                              console_logs(out_dir, mcus))});
    }

    RunOutcome outcome;
    // An MCU that stopped has its report already; what it never reached is no wiring mistake, and
    // nor is anything in a run stopped before its clock moved (a `sear view` left waiting for a page).
    const bool nothing_ran = interrupted && sim.time_ns() == 0;
    for (std::size_t i = 0; i < lockstep.mcu_count() && !nothing_ran; ++i)
      if (!lockstep.mcu(i).failure())
        for (auto& note : wiring_notes(lockstep.mcu(i))) outcome.wiring.push_back(std::move(note));
    // Once, at the end, where the user looks: a run that completed can still have been useless.
    for (const auto& note : outcome.wiring)
      fmt::print(stderr, "sear: {}: {}\n", note.kind == WiringNote::Kind::Unused ? "wiring" : "note", note.text);
    outcome.import_warnings = import_warnings;
    outcome.project_file = path;
    outcome.project_name = project->name;
    outcome.seed = project->run.seed;
    outcome.wall_time_s = seconds_since(start);
    outcome.step_wall = lockstep.wall_time();
    outcome.mcu_stops = lockstep.stops();
    outcome.mcu_halts = lockstep.halts();
    outcome.never_sent = capture.never_sent();
    outcome.host_ports = host_ports.final_listing();
    outcome.avr_reports = avr_reports;
    outcome.status = interrupted        ? "interrupted"
                     : physics_failed   ? "physics failed"
                     : !outcome.mcu_stops.empty() ? "mcu stopped"
                                                  : "completed";
    if (controller_gone) outcome.status = "lcm controller gone";
    if (checker)
      for (const auto& r : checker->results())
        outcome.expectations.push_back({r.expectation->name,
                                        r.verdict == Verdict::Passed   ? "passed"
                                        : r.verdict == Verdict::Failed ? "failed"
                                                                       : "undecided",
                                        static_cast<double>(r.time_ns) * 1e-9, r.seen});
    std::vector<const BoundedFile*> outputs = trace.outputs();
    for (const auto* f : capture.outputs()) outputs.push_back(f);
    for (const auto* f : can_logs.outputs()) outputs.push_back(f);
    for (const auto* f : sensors.outputs()) outputs.push_back(f);
    for (const auto* f : outputs)
      if (f->truncated()) outcome.truncated_files.push_back(f->path());
    for (auto& log : note_truncated_host_logs(out_dir, mcus, max_file_bytes))
      outcome.truncated_files.push_back(std::move(log));
    for (const auto& f : outcome.truncated_files)
      fmt::print(stderr, "sear: {} reached its limit of {} bytes (--max-file-mb) and was cut short\n", f, max_file_bytes);
    const std::string text = summary_text(sim, outcome);
    write_file(out_dir + "/summary.txt", text);
    write_file(out_dir + "/summary.json", summary_json(sim, outcome));
    if (!options.quiet) print_to_stdout(text);
    // After everything is on disk, from those files, in the background: a plot that fails costs a
    // warning, never the run, and drawing them costs the run no time, unless asked to wait.
    const bool drawing = plots && !interrupted && plot_folder.draw_in_background();
    if (drawing && options.wait_plots) PlotFolder::wait_for_plotter(out_dir);
    if (!options.quiet)
      print_to_stdout(output_line(out_dir, outputs) +
                      (drawing && !options.wait_plots
                           ? fmt::format("\n  plots: drawn in the background into {}/ (`flock {} true` waits for them)",
                                         out_dir, out_dir)
                           : "") +
                      "\n");
    // `sear view` shows the end until Ctrl-C, or starts over when the page says so.
    if (view && view->end_run(sim, outcome.status, options.view_keep_serving) == ViewSession::Gate::Reset) {
      fmt::print(stderr, "sear: reset by the viewer: the run starts over at t = 0\n");
      goto start_over;
    }
    if (interrupted) {
      fmt::print(stderr, "sear: {}\n", interrupted_status());
      return interrupted_exit_code();
    }
    if (physics_failed) return 4;
    if (controller_gone) return kLcmControllerGoneExitCode;
    if (checker && !checker->passed()) return kExpectationFailedExitCode;
    return outcome.mcu_stops.empty() ? 0 : 3;
  } catch (const PlacementError& e) {
    print_world_errors(path, e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
}

}  // namespace sear
