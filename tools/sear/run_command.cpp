#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "exporters/mcu_capture.hpp"
#include "exporters/run_summary.hpp"
#include "exporters/trace_csv.hpp"
#include "scene/project_loader.hpp"
#include "sear/commands.hpp"
#include "sear/firmware_builder.hpp"

namespace sear {
namespace {

std::atomic<bool> g_stop_requested{false};

extern "C" void request_stop(int) { g_stop_requested = true; }

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error(path + ": error: cannot write");
}

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

int run_command(const RunOptions& options) {
  Diagnostics diagnostics;
  const std::string path = resolve_project_path(options.project);
  auto project = load_project(path, diagnostics);
  if (!project) {
    fmt::print(stderr, "{}", diagnostics.joined());
    return 1;
  }
  if (options.duration_s) project->run.duration_s = *options.duration_s;
  if (options.seed) project->run.seed = *options.seed;
  if (options.trace_rate_hz) project->run.trace_rate_hz = *options.trace_rate_hz;

  try {
    build_project_firmware(*project, options.quiet);
  } catch (const FirmwareBuildError& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }

  try {
    std::filesystem::create_directories(options.out_dir);
    Simulation sim(*project, project->run.seed);
    TraceCsv trace(options.out_dir, sim);
    std::vector<McuCapture::Mcu> mcus;
    for (const auto& robot : project->robots)
      for (const auto& mcu : robot.mcus) mcus.push_back({robot.name + "." + mcu.name, mcu.console_uart});
    McuCapture capture(options.out_dir, mcus, !options.quiet);
    Lockstep lockstep(sim, *project, {options.out_dir, options.hang_timeout_s, options.keep_going}, capture);
    const std::int64_t end_ns = std::llround(project->run.duration_s * 1e9);
    const std::int64_t trace_every =
        std::max<std::int64_t>(1, std::llround(1e9 / project->run.trace_rate_hz / static_cast<double>(sim.step_ns())));

    // Ctrl-C ends the run early but still writes the summary, so nothing done so far is lost.
    std::signal(SIGINT, request_stop);
    std::signal(SIGTERM, request_stop);
    const bool show_progress = !options.quiet && isatty(STDERR_FILENO);
    const auto start = Clock::now();
    double next_progress_s = 2.0;  // short runs finish before a progress line would help

    trace.write_row(sim);
    std::int64_t steps = 0;
    std::size_t stops_reported = 0;
    while (sim.time_ns() < end_ns && !g_stop_requested) {
      const bool go_on = lockstep.step();
      for (; stops_reported < lockstep.stops().size(); ++stops_reported) {
        if (show_progress && next_progress_s > 2.0) fmt::print(stderr, "\n");
        fmt::print(stderr, "sear: {} (its output: {}/{}.host.log)\n", describe(lockstep.stops()[stops_reported]),
                   options.out_dir, lockstep.stops()[stops_reported].mcu);
      }
      if (!go_on) break;
      if (++steps % trace_every == 0) trace.write_row(sim);
      if (show_progress && (steps & 1023) == 0 && seconds_since(start) >= next_progress_s) {
        next_progress_s += 0.5;
        const double wall = seconds_since(start);
        fmt::print(stderr, "\r  {:.1f} / {:.1f} s simulated ({:.0f}%), {:.1f}x real time ", sim.time_s(),
                   project->run.duration_s, 100.0 * sim.time_s() / project->run.duration_s, sim.time_s() / wall);
      }
    }
    if (show_progress && next_progress_s > 2.0) fmt::print(stderr, "\n");
    trace.flush();
    capture.finish();

    RunOutcome outcome;
    outcome.project_file = path;
    outcome.project_name = project->name;
    outcome.seed = project->run.seed;
    outcome.wall_time_s = seconds_since(start);
    outcome.mcu_stops = lockstep.stops();
    outcome.status = g_stop_requested ? "interrupted" : !outcome.mcu_stops.empty() ? "mcu stopped" : "completed";
    const std::string text = summary_text(sim, outcome);
    write_file(options.out_dir + "/summary.txt", text);
    write_file(options.out_dir + "/summary.json", summary_json(sim, outcome));
    if (!options.quiet) {
      fmt::print("{}", text);
      fmt::print("  output: {}/ (summary.txt, summary.json", options.out_dir);
      for (const auto& f : trace.files()) fmt::print(", {}", std::filesystem::path(f).filename().string());
      for (const auto& f : capture.files()) fmt::print(", {}", std::filesystem::path(f).filename().string());
      fmt::print(")\n");
    }
    if (g_stop_requested) return 130;
    return outcome.mcu_stops.empty() ? 0 : 3;
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
}

}  // namespace sear
