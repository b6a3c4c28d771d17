// The bundled obstacle avoider, unmodified, drives the default world (as
// assets/projects/avoider_hills.xml has it): a minute without touching a wall, and the same bytes
// out from two runs.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "firmware_run.hpp"

namespace sear::test {
namespace {

SearRun run_default(const TempDir& dir, const std::string& name) {
  const auto out = dir.path() / name;
  const std::string cmd = std::string(SEAR_BINARY) + " run " SEAR_ASSET_DIR "/projects/avoider_hills.xml --quiet --duration 60 -o " +
                          out.string() + " 2>" +
                          (dir.path() / (name + ".err")).string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, "", read_file(dir.path() / (name + ".err")), out};
}

TEST(Avoider, DrivesTheDefaultWorldForAMinuteWithoutTouchingAWallTheSameWayTwice) {
  TempDir dir;
  const auto a = run_default(dir, "a");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto summary = nlohmann::json::parse(a.file("summary.json"));
  EXPECT_DOUBLE_EQ(summary["sim_time_s"].get<double>(), 60.0);
  for (const auto& c : summary["collision_events"])
    EXPECT_EQ(c["other"].get<std::string>().find("_wall"), std::string::npos) << c.dump();
  // It went somewhere: a robot that never moved would not touch a wall either.
  EXPECT_GT(summary["robots"][0]["distance_m"].get<double>(), 10.0);
  const std::string console = a.file("rover.main.console.log");
  EXPECT_EQ(console.rfind("0.00", 0), 0u) << console.substr(0, 200);
  EXPECT_NE(console.find("avoider: ready"), std::string::npos);

  const auto b = run_default(dir, "b");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  for (const char* file : {"trace_rover.csv", "rover.main.console.log", "rover.main.pins.vcd", "rover.main.uart0.log",
                           "rover.main.uart0.tx.bin"})
    EXPECT_TRUE(a.file(file) == b.file(file)) << file << " differs between two runs";
}

}  // namespace
}  // namespace sear::test
