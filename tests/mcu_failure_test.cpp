// A firmware that crashes, exits, hangs or asks the HAL for the impossible ends the run with a
// report naming the MCU, the cause, the sim time and the last HAL call, and loses no output.
#include <gtest/gtest.h>

#include <cstdio>
#include <nlohmann/json.hpp>

#include "firmware_run.hpp"

namespace sear::test {
namespace {

std::string one_mcu(const char* executable) {
  return std::string(R"(    <mcu name="main">
      <firmware executable=")") + executable + R"("/>
    </mcu>
)";
}

struct Expected {
  const char* executable;
  const char* kind;
  const char* cause;
  const char* last_call;
  // 300 ms after delay_ms(300) began, which followed three HAL calls of 3.125 us (50 cycles at
  // 16 MHz) each; a refused call is reported with its own cost already charged.
  double time_s = 0.300009375;
};

void expect_report(const SearRun& run, const Expected& e) {
  EXPECT_EQ(run.exit_code, 3) << run.err;
  // It stopped at 300 ms of its own clock, inside or right after delay_ms(300).
  const std::string report = std::string("mcu rover.main ") + e.cause;
  EXPECT_NE(run.err.find(report), std::string::npos) << run.err;
  char at[64];
  std::snprintf(at, sizeof at, "at sim time %.6f s", e.time_s);
  EXPECT_NE(run.err.find(at), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("s; last HAL call: " + std::string(e.last_call)), std::string::npos) << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_EQ(summary["status"], "mcu stopped");
  ASSERT_EQ(summary["mcu_stops"].size(), 1u);
  EXPECT_EQ(summary["mcu_stops"][0]["mcu"], "rover.main");
  EXPECT_EQ(summary["mcu_stops"][0]["kind"], e.kind);
  EXPECT_NEAR(summary["mcu_stops"][0]["sim_time_s"].get<double>(), e.time_s, 1e-12);
  EXPECT_EQ(summary["mcu_stops"][0]["last_hal_call"], e.last_call);
  // What it printed before failing, and the trace up to then, are on disk.
  EXPECT_NE(run.file("rover.main.console.log").find("about to fail"), std::string::npos);
  // And what it printed on its own stdout, a file, where a buffer would have lost it.
  EXPECT_NE(run.file("rover.main.host.log").find("on its own stdout before failing"), std::string::npos);
  EXPECT_GE(lines_of(run.file("trace_rover.csv")).size(), 4u);  // header, t = 0, 0.1, 0.2 s
}

TEST(McuFailure, ACrashIsReportedWithItsSignal) {
  TempDir dir;
  expect_report(run_sear(dir, rover_project(one_mcu(CRASH_PROBE))),
                {CRASH_PROBE, "crashed", "crashed with signal 11 (SIGSEGV", "delay_ms"});
}

TEST(McuFailure, AnExitIsReportedWithItsCode) {
  TempDir dir;
  const auto run = run_sear(dir, rover_project(one_mcu(EXIT_PROBE)));
  expect_report(run, {EXIT_PROBE, "exited", "exited with code 3", "delay_ms"});
  // Its destructor's HAL calls, after exit(), neither hang the run nor reach the logs.
  EXPECT_EQ(run.file("rover.main.console.log").find("goodbye"), std::string::npos);
}

TEST(McuFailure, AFirmwareThatStopsCallingTheHalIsReportedAsHungAndStopped) {
  TempDir dir;
  expect_report(run_sear(dir, rover_project(one_mcu(HANG_PROBE)), "--hang-timeout 0.5"),
                {HANG_PROBE, "hung", "hung: its clock stood still for 0.5 s of host time", "delay_ms"});
}

TEST(McuFailure, ACallTheChipCannotDoStopsTheFirmwareWithTheReason) {
  TempDir dir;
  expect_report(run_sear(dir, rover_project(one_mcu(REFUSE_PROBE))),
                {REFUSE_PROBE, "refused", "stopped by the HAL: pwm_write(22): on the ATmega2560 board only pins", "pwm_write", 0.3000125});
}

TEST(McuFailure, KeepGoingRunsToTheEndWithoutThatMcuAndStillFails) {
  TempDir dir;
  const std::string mcus = one_mcu(CRASH_PROBE) + R"(    <mcu name="other">
      <firmware executable=")" + TIMER_PROBE + R"("/>
    </mcu>
)";
  const auto run = run_sear(dir, rover_project(mcus, "", 1.05), "--keep-going");
  EXPECT_EQ(run.exit_code, 3) << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_DOUBLE_EQ(summary["sim_time_s"].get<double>(), 1.05);
  ASSERT_EQ(summary["mcu_stops"].size(), 1u);
  EXPECT_EQ(summary["mcu_stops"][0]["mcu"], "rover.main");
  EXPECT_NE(run.file("rover.other.console.log").find(" ticks 1"), std::string::npos);
}

TEST(McuFailure, FirmwareThatDoesNotCompileStopsTheRunWithTheCompilersFileAndLine) {
  TempDir dir;
  dir.write("broken.c", "#include <hal/hal.h>\nint main(void) {\n  hal_init()\n  return 0;\n}\n");
  const std::string project = rover_project("    <mcu name=\"main\">\n      <firmware sources=\"broken.c\"/>\n    </mcu>\n");
  const auto run = run_sear(dir, project, "");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("firmware 'rover.main' failed to build"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("broken.c:3:"), std::string::npos) << run.err;  // the missing ';'
  EXPECT_FALSE(std::filesystem::exists(run.dir / "summary.json"));
}

}  // namespace
}  // namespace sear::test
