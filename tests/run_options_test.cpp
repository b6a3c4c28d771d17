// Run options at non-default values and the outputs a user reads, each held to what the run
// itself shows: the world's step and --trace-rate shape the trace's time column and the step
// count; every field of summary.json against the trace it came with; the status, exit code, stop
// code and detail of each way a run ends; and the seed: the same seed gives the same bytes, a
// different one changes what is noisy.
#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <regex>

#include "devices/sharp_gp2d12.h"
#include "model_run.hpp"
#include "scoped_env.hpp"

namespace sear::test {
namespace {

// The rover of rover_project, with `mcus`, on a world whose step is `step`.
std::string project_with_step(const std::string& mcus, const std::string& world_extra, double duration_s,
                              const std::string& step) {
  std::string p = rover_project(mcus, world_extra, duration_s);
  const std::string default_step = "<world step=\"0.001\">";
  p.replace(p.find(default_step), default_step.size(), "<world step=\"" + step + "\">");
  return p;
}

const std::string kDriveOn = "    <script>\n      <motor t=\"0\" name=\"left\" duty=\"1\"/>\n"
                             "      <motor t=\"0\" name=\"right\" duty=\"1\"/>\n    </script>\n";

std::string one_mcu(const char* executable) {
  return std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + executable + "\"/>\n    </mcu>\n";
}

std::string fixed6(double x) {
  char s[32];
  std::snprintf(s, sizeof s, "%.6f", x);
  return s;
}

// A 2 ms world step (not the default 1 ms), the project's own duration, seed and trace rate
// overridden on the command line: a trace row at t = 0, then one every `steps_per_row` steps of
// 2 ms up to the end at 1.2 s (600 steps).
void expect_trace_rows(const char* rate_hz, int steps_per_row) {
  TempDir dir;
  const auto run = run_sear(dir, project_with_step(kDriveOn, "", 5.0, "0.002"),
                            std::string("--duration 1.2 --seed 9 --trace-rate ") + rate_hz);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Trace trace(run.file("trace_rover.csv"));
  const int every_ms = 2 * steps_per_row;
  const auto& times = trace.time_cells();
  ASSERT_EQ(times.size(), static_cast<std::size_t>(1200 / every_ms + 1)) << "rows every " << every_ms << " ms";
  for (std::size_t k = 0; k < times.size(); ++k)
    EXPECT_EQ(times[k], fixed6(static_cast<double>(k) * every_ms * 1e-3)) << "row " << k;
  // The rover moved between rows: the rows are the world at those times, not one state repeated.
  EXPECT_GT(trace.last("x_m") - trace.at(0, "x_m"), 0.3);
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_EQ(summary["status"], "completed");
  EXPECT_EQ(summary["seed"], 9);
  EXPECT_EQ(summary["steps"], 600);  // 1.2 s / 2 ms
  // A lone rover's group of bodies, about 33 rows, is the direct solver's every step.
  EXPECT_EQ(summary["solver_steps"]["direct"], 600);
  EXPECT_EQ(summary["solver_steps"]["iterative"], 0);
  EXPECT_EQ(summary["solver_steps"]["retaken"], 0);
  EXPECT_DOUBLE_EQ(summary["sim_time_s"].get<double>(), 600 * 0.002);
  EXPECT_TRUE(summary["mcu_stops"].empty());
}

TEST(TraceRate, ThirtyHzWith2msStepsIsARowEvery17Steps) {
  // 1/30 s is 16.67 steps of 2 ms: rounded, 17 steps, 34 ms (flooring would give 32 ms).
  expect_trace_rows("30", 17);
}

TEST(TraceRate, ThirtyPointFiveHzWith2msStepsIsARowEvery16Steps) {
  // 1/30.5 s is 16.39 steps of 2 ms: rounded, 16 steps, 32 ms (the ceiling would give 34 ms).
  expect_trace_rows("30.5", 16);
}

TEST(RunSummary, EveryFieldAUserReadsMatchesTheRunItDescribes) {
  // The rover drives at full duty into a box, 2 ms steps, a trace row every step, seed 42; its
  // MCU crashes at 0.3 s and --keep-going runs on without it.
  const double face = 0.9;  // the box's west face, 0.75 m ahead of the rover's nose
  TempDir dir;
  const auto run = run_sear(dir,
                            project_with_step(kDriveOn + one_mcu(CRASH_PROBE),
                                              "    <box name=\"target\" pos=\"" + std::to_string(face + 0.1) +
                                                  " 0\" size=\"0.2 1 0.3\"/>\n",
                                              2.0, "0.002"),
                            "--seed 42 --trace-rate 500 --keep-going");
  ASSERT_EQ(run.exit_code, 3) << run.err;
  const auto s = nlohmann::json::parse(run.file("summary.json"));
  const Trace trace(run.file("trace_rover.csv"));
  ASSERT_EQ(trace.times_us().size(), 1001u);  // t = 0 and every one of the 1000 steps

  EXPECT_EQ(s["project"], "test");
  EXPECT_EQ(s["project_file"], (dir.path() / "project.xml").string());
  EXPECT_EQ(s["seed"], 42);
  EXPECT_EQ(s["status"], "mcu stopped");
  EXPECT_EQ(s["steps"], 1000);
  EXPECT_DOUBLE_EQ(s["sim_time_s"].get<double>(), 1000 * 0.002);
  EXPECT_GT(s["wall_time_s"].get<double>(), 0.0);
  EXPECT_NEAR(s["real_time_factor"].get<double>(), s["sim_time_s"].get<double>() / s["wall_time_s"].get<double>(),
              1e-9 * s["real_time_factor"].get<double>());
  // Where a step's wall time went, in microseconds a step: each part took some (a clock read
  // apart at least), the world's step more than nothing, and the 1000 steps together no more
  // than the whole run, which also started the firmware and wrote the files.
  double per_step_us = 0;
  for (const char* part : {"before_quantum", "capture", "physics", "after_quantum"}) {
    ASSERT_TRUE(s["step_wall_us"].contains(part)) << part;
    EXPECT_GE(s["step_wall_us"][part].get<double>(), 0.0) << part;
    per_step_us += s["step_wall_us"][part].get<double>();
  }
  EXPECT_GT(s["step_wall_us"]["physics"].get<double>(), 0.0);
  EXPECT_LE(per_step_us * 1000, s["wall_time_s"].get<double>() * 1e6);

  ASSERT_EQ(s["robots"].size(), 1u);
  const auto& robot = s["robots"][0];
  EXPECT_EQ(robot["name"], "rover");
  // A rover upright on flat ground, pushing on a box, is still running, with no robot event, no
  // physics failure and no file cut short.
  EXPECT_EQ(robot["status"], "running");
  EXPECT_TRUE(s["robot_events"].empty()) << s["robot_events"].dump();
  EXPECT_TRUE(s["physics_failure"].is_null()) << s["physics_failure"].dump();
  EXPECT_TRUE(s["truncated_files"].empty()) << s["truncated_files"].dump();
  // The horizontal path length, summed step by step as the trace shows it: each of its
  // coordinates is rounded to 0.5e-6 m, so each step's length to within 1.5e-6 m.
  double path = 0;
  const auto& t = trace.times_us();
  for (std::size_t i = 1; i < t.size(); ++i)
    path += std::hypot(trace.at(t[i], "x_m") - trace.at(t[i - 1], "x_m"), trace.at(t[i], "y_m") - trace.at(t[i - 1], "y_m"));
  EXPECT_NEAR(robot["distance_m"].get<double>(), path, 1.5e-6 * static_cast<double>(t.size()));
  EXPECT_GT(path, 0.5);
  const auto& final_position = robot["final_position_m"];
  ASSERT_EQ(final_position.size(), 3u);
  EXPECT_NEAR(final_position[0].get<double>(), trace.last("x_m"), 0.5e-6);
  EXPECT_NEAR(final_position[1].get<double>(), trace.last("y_m"), 0.5e-6);
  EXPECT_NEAR(final_position[2].get<double>(), trace.last("z_m"), 0.5e-6);
  EXPECT_NEAR(robot["final_yaw_rad"].get<double>(), trace.last("yaw_rad"), 0.5e-6);

  // The collision: the rover against the box, at the end of the step in which the box stopped
  // it (the first row where its speed falls by more than half in one step: from about 0.7 m/s,
  // where nothing but the box can take that much in 2 ms), with the chassis's nose then at the
  // face, to within one step's travel (1.4 mm) and ODE's contact margin.
  ASSERT_GE(s["collision_events"].size(), 1u);
  EXPECT_EQ(robot["collisions"], s["collision_events"].size());
  for (const auto& e : s["collision_events"]) {
    EXPECT_EQ(e["robot"], "rover");
    EXPECT_EQ(e["other"], "target");
  }
  const double event_s = s["collision_events"][0]["time_s"].get<double>();
  long long stopped_us = -1;
  for (std::size_t i = 1; i < t.size() && stopped_us < 0; ++i)
    if (trace.at(t[i - 1], "vx_mps") > 0.5 && trace.at(t[i], "vx_mps") < 0.5 * trace.at(t[i - 1], "vx_mps")) stopped_us = t[i];
  ASSERT_GE(stopped_us, 0) << "the rover never hit the box";
  EXPECT_NEAR(event_s, static_cast<double>(stopped_us) * 1e-6, 1e-9);
  const Pose at_stop = pose_at(trace, stopped_us);
  double nose = -1e9;
  for (const double y : {-0.09, 0.09})
    for (const double z : {-0.03, 0.03}) nose = std::max(nose, at_stop.p.x + at_stop.rotate({0.15, y, z}).x);
  EXPECT_NEAR(nose, face, 0.002);

  ASSERT_EQ(s["mcu_stops"].size(), 1u);
  const auto& stop = s["mcu_stops"][0];
  EXPECT_EQ(stop["mcu"], "rover.main");
  EXPECT_EQ(stop["kind"], "crashed");
  EXPECT_EQ(stop["code"], SIGSEGV);
  EXPECT_EQ(stop["detail"], "SIGSEGV, Segmentation fault");
  // 300 ms after delay_ms(300) began, which followed three calls of 3125 ns.
  EXPECT_DOUBLE_EQ(stop["sim_time_s"].get<double>(), 0.300009375);
  EXPECT_EQ(stop["last_hal_call"], "delay_ms");

  // summary.txt says the same, rounded for people.
  const std::string text = run.file("summary.txt");
  char expect[256];
  std::snprintf(expect, sizeof expect, "robot rover: distance %.2f m, collisions %d, final position (%.2f, %.2f, %.2f) m",
                robot["distance_m"].get<double>(), robot["collisions"].get<int>(), final_position[0].get<double>(),
                final_position[1].get<double>(), final_position[2].get<double>());
  EXPECT_NE(text.find(expect), std::string::npos) << text;
  EXPECT_NE(text.find("seed 42: mcu stopped"), std::string::npos) << text;
  EXPECT_NE(text.find("sim time 2.000 s"), std::string::npos) << text;
  std::snprintf(expect, sizeof expect, "collision at %.3f s: rover hit target", event_s);
  EXPECT_NE(text.find(expect), std::string::npos) << text;
}

struct StopCase {
  const char* executable;
  const char* kind;
  int code;
  const char* detail;  // the start of it
  const char* last_call;
  double time_s;
};

void expect_stop(const StopCase& c) {
  TempDir dir;
  const auto run = run_sear(dir, rover_project(one_mcu(c.executable)));
  EXPECT_EQ(run.exit_code, 3) << run.err;
  const auto s = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_EQ(s["status"], "mcu stopped");
  // The run stopped at the step the MCU stopped in, the one from 0.300 to 0.301 s (which holds
  // 0.300009 s), finished or not; its time is a whole number of steps.
  EXPECT_GE(s["steps"], 300);
  EXPECT_LE(s["steps"], 301);
  EXPECT_DOUBLE_EQ(s["sim_time_s"].get<double>(), s["steps"].get<double>() * 0.001);
  ASSERT_EQ(s["mcu_stops"].size(), 1u);
  const auto& stop = s["mcu_stops"][0];
  EXPECT_EQ(stop["mcu"], "rover.main");
  EXPECT_EQ(stop["kind"], c.kind);
  EXPECT_EQ(stop["code"], c.code);
  EXPECT_EQ(stop["detail"].get<std::string>().rfind(c.detail, 0), 0u) << stop.dump();
  EXPECT_DOUBLE_EQ(stop["sim_time_s"].get<double>(), c.time_s);
  EXPECT_EQ(stop["last_hal_call"], c.last_call);
}

TEST(StopKind, AnExitIsReportedWithItsCodeAndNoDetail) {
  // exit(3) after delay_ms(300), which began after three calls of 3125 ns.
  expect_stop({EXIT_PROBE, "exited", 3, "", "delay_ms", 0.300009375});
}

TEST(StopKind, ARefusedCallIsReportedWithTheHalsReasonAndNoCode) {
  // pwm_write(22, ...) on a pin without a timer; its own call's cost is charged first.
  expect_stop({REFUSE_PROBE, "refused", 0, "pwm_write(22): on the ATmega2560 board only pins", "pwm_write", 0.3000125});
}

// A physics failure ends the run with its documented exit code, 4, the status "physics failed"
// and the report in the summary, and what was written up to there stays whole. The failure is
// made on purpose (tests/physics_fault_preload.c, preloaded into sear): after ODE's 250th step of
// 1 ms the rover's first body has a NaN velocity, which the check after that step finds.
TEST(RunStatus, APhysicsFailureEndsTheRunWithCode4AndItsReport) {
  TempDir dir;
#ifdef __SANITIZE_ADDRESS__
  // In a sanitizer build sear and its firmware want ASan's runtime first among their libraries,
  // and the preloaded library (built without the sanitizers, as the shell loads it too) comes
  // before it; it interposes no allocation function, which is what that order is checked for.
  const char* asan_options = std::getenv("ASAN_OPTIONS");
  const ScopedEnv link_order("ASAN_OPTIONS", std::string(asan_options ? asan_options : "") +
                                                 (asan_options ? ":" : "") + "verify_asan_link_order=0");
#endif
  SearRun run;
  {
    const ScopedEnv preload("LD_PRELOAD", PHYSICS_FAULT_PRELOAD);
    const ScopedEnv break_step("SEAR_TEST_BREAK_STEP", "250");
    run = run_sear(dir, rover_project(kDriveOn, "", 1.0));
  }
  EXPECT_EQ(run.exit_code, 4) << run.err;
  EXPECT_NE(run.err.find("sear: physics failed at sim time 0.250000 s: robot 'rover'"), std::string::npos) << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_EQ(summary["status"], "physics failed");
  ASSERT_TRUE(summary["physics_failure"].is_string());
  EXPECT_NE(summary["physics_failure"].get<std::string>().find("a non-finite state"), std::string::npos);
  EXPECT_DOUBLE_EQ(summary["sim_time_s"].get<double>(), 0.25);  // the step in which it broke
  // The trace has every row due before the failure (every 100 ms from 0) and they are finite.
  const Trace trace(run.file("trace_rover.csv"));
  EXPECT_EQ(trace.times_us(), (std::vector<long long>{0, 100000, 200000}));
  EXPECT_TRUE(std::isfinite(trace.last("x_m")));
}

TEST(RunStatus, CtrlCEndsTheRunInterruptedWithCode130AndASummaryOfTheStepsDone) {
  TempDir dir;
  // A run far too long to finish, interrupted by SIGINT once its trace holds a few rows (waited
  // for, not timed, so that a slow start on a loaded machine changes nothing).
  const auto project = dir.path() / "project.xml";
  std::ofstream(project) << rover_project(kDriveOn + one_mcu(IR_PROBE), "", 1000);
  const auto out = dir.path() / "out";
  const std::string trace_file = (out / "trace_rover.csv").string();
  const std::string cmd = "bash -c '" + std::string(SEAR_BINARY) + " run " + project.string() + " -o " + out.string() +
                          " --quiet 2>" + (dir.path() / "stderr").string() + " & p=$!; for i in $(seq 600); do " +
                          "[ \"$(stat -c %s " + trace_file + " 2>/dev/null || echo 0)\" -gt 2000 ] && break; sleep 0.05; done; " +
                          "kill -INT $p; wait $p'";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130) << read_file(dir.path() / "stderr");
  const auto s = nlohmann::json::parse(read_file(out / "summary.json"));
  EXPECT_EQ(s["status"], "interrupted");
  EXPECT_TRUE(s["mcu_stops"].empty()) << s.dump();
  const double sim_s = s["sim_time_s"].get<double>();
  EXPECT_GT(sim_s, 0.0);
  EXPECT_LT(sim_s, 1000.0);
  EXPECT_DOUBLE_EQ(sim_s, s["steps"].get<double>() * 0.001);
  // The trace is complete up to the stop: a row every 100 ms (trace_rate 10), up to sim_time_s.
  const Trace trace(read_file(out / "trace_rover.csv"));
  EXPECT_EQ(static_cast<long long>(trace.times_us().size()), s["steps"].get<long long>() / 100 + 1);
}

// A noisy run: four GP2D12s with 50 mV of noise in front of boxes at 20..50 cm.
std::string noisy_project() {
  std::string mcu = std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + IR_PROBE + "\"/>\n";
  std::string boxes;
  const double ys[] = {-0.075, -0.025, 0.025, 0.075};
  for (int i = 0; i < 4; ++i) {
    mcu += "      <gp2d12 name=\"ir" + std::to_string(i) + "\" adc=\"" + std::to_string(i) + "\" pos=\"0.15 " +
           std::to_string(ys[i]) + " 0.02\" half_angle_deg=\"0\" noise_v=\"0.05\"/>\n";
    boxes += "    <box name=\"target" + std::to_string(i) + "\" pos=\"" + std::to_string(0.15 + 0.2 + 0.1 * i + 0.01) +
             " " + std::to_string(ys[i]) + "\" size=\"0.02 0.03 0.3\"/>\n";
  }
  return rover_project(mcu + "    </mcu>\n", boxes, 2.05);
}

// A summary.txt with the line naming host wall time taken out, and the run's own folder renamed.
std::string without_wall_time(const std::string& text, const std::string& folder) {
  std::string out;
  for (auto line : lines_of(text)) {
    if (line.find("wall time") != std::string::npos) continue;
    for (auto at = line.find(folder); at != std::string::npos; at = line.find(folder)) line.replace(at, folder.size(), "DIR");
    out += line + "\n";
  }
  return out;
}

TEST(Determinism, TheSameSeedGivesTheSameBytesAndAnotherSeedOtherNoise) {
  TempDir a, b, c;
  const auto run_a = run_sear(a, noisy_project(), "--seed 5");
  const auto run_b = run_sear(b, noisy_project(), "--seed 5");
  const auto run_c = run_sear(c, noisy_project(), "--seed 6");
  for (const auto* r : {&run_a, &run_b, &run_c}) ASSERT_EQ(r->exit_code, 0) << r->err;
  for (const char* file : {"trace_rover.csv", "rover.main.console.log", "rover.main.pins.vcd", "rover.main.uart0.log",
                           "rover.main.uart0.tx.bin"})
    EXPECT_TRUE(run_a.file(file) == run_b.file(file)) << file << " differs between two runs of seed 5";
  // summary.json differs only in project_file (each run's own folder) and the wall time.
  auto sa = nlohmann::json::parse(run_a.file("summary.json")), sb = nlohmann::json::parse(run_b.file("summary.json"));
  for (auto* s : {&sa, &sb})
    for (const char* key : {"project_file", "wall_time_s", "real_time_factor", "step_wall_us"}) s->erase(key);
  EXPECT_EQ(sa, sb);
  EXPECT_EQ(without_wall_time(run_a.file("summary.txt"), a.path().string()),
            without_wall_time(run_b.file("summary.txt"), b.path().string()));

  // Seed 6: other noise, so other readings.
  const std::string console_a = run_a.file("rover.main.console.log"), console_c = run_c.file("rover.main.console.log");
  EXPECT_NE(console_a, console_c);
  // And the readings scatter as 50 mV of Gaussian noise should, around the noiseless curve at the
  // distances the trace shows, in both seeds: a standard deviation of 0.05 V * 1024 / 5 V = 10.24
  // codes (plus 1/12 code^2 of quantisation); the mean residual is -0.5 code (truncation).
  for (const auto* run : {&run_a, &run_c}) {
    const Trace trace(run->file("trace_rover.csv"));
    double sum = 0, sum2 = 0;
    int n = 0, different_from_first = 0;
    std::string first;
    for (const auto& line : lines_of(run->file("rover.main.console.log"))) {
      std::smatch m;
      ASSERT_TRUE(std::regex_search(line, m, std::regex("^(\\d+\\.\\d+) adc (\\d+) (\\d+) (\\d+) (\\d+)$"))) << line;
      const double t_s = std::stod(m[1]);
      if (t_s < 0.3) continue;  // the rover settles on its wheels first
      // The pose of the nearest trace row (every 100 ms): the unpowered rover creeps under
      // 1 mm/s, so that is within 0.05 mm of where it was, 0.01 code at these distances.
      const Pose pose = pose_at(trace, std::llround(t_s * 10) * 100000);
      for (int i = 0; i < 4; ++i) {
        const double ys[] = {-0.075, -0.025, 0.025, 0.075};
        const double d = axis_distance_to_x_plane(pose, {0.15, ys[i], 0.02}, 0.15 + 0.2 + 0.1 * i);
        const double r = std::stod(m[i + 2]) - gp2d12_output_v(d) * 1024 / 5.0;
        sum += r;
        sum2 += r * r;
        ++n;
      }
      if (first.empty()) first = line.substr(line.find(' '));
      else if (line.substr(line.find(' ')) != first) ++different_from_first;
    }
    ASSERT_GE(n, 64);  // 17 lines of 4 readings from 0.3 s to 2 s
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    const double sigma = std::sqrt(10.24 * 10.24 + 1.0 / 12);
    // For n >= 64 samples the sample deviation lies within +-30 % of sigma far beyond 3 standard
    // errors (sigma / sqrt(2n), under 9 %); the mean within 4 sigma / sqrt(n) of -0.5.
    EXPECT_NEAR(sd, sigma, 0.3 * sigma) << "seed run " << run->dir;
    EXPECT_NEAR(mean, -0.5, 4 * sigma / std::sqrt(n)) << "seed run " << run->dir;
    EXPECT_GT(different_from_first, 10);  // each line is a new measurement with its own noise
  }
}

}  // namespace
}  // namespace sear::test
