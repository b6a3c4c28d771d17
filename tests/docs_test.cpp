// What docs/outputs.md says of the outputs is generated from the same lists the code writes them
// from: the trace's columns, as the header of a run's trace_<robot>.csv has them.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <set>

#include "exporters/trace_csv.hpp"
#include "firmware_run.hpp"

namespace sear::test {
namespace {

TEST(Docs, TheOutputsPageDescribesTheTraceColumnsAsTheFileHasThem) {
  const std::string outputs = read_file(std::string(SEAR_ASSET_DIR) + "/../docs/outputs.md");
  const std::string row = "| `trace_<robot>.csv` | One row per trace period, starting at t = 0: " +
                          trace_columns_markdown() + " |";
  EXPECT_NE(outputs.find(row), std::string::npos) << "docs/outputs.md's row for the trace should read\n" << row;
}

// The header of a real run's trace: the fixed columns in the list's order, then the rover's two
// wheels and two motors, each motor's duty and mode together.
TEST(Docs, TheTraceHeaderFollowsTheList) {
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project("", "", 0.01), "--quiet");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string header = lines_of(run.file("trace_rover.csv")).at(0);
  std::string fixed;
  for (const TraceColumn& c : trace_columns())
    if (c.per == TracePer::Robot) fixed += std::string(fixed.empty() ? "" : ",") + c.name;
  EXPECT_EQ(header.substr(0, fixed.size()), fixed);
  EXPECT_EQ(fixed, "time_s,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad,vx_mps,vy_mps,vz_mps,wx_radps,wy_radps,wz_radps,"
                   "forward_mps");
  EXPECT_EQ(header.substr(fixed.size()),
            ",wheel_left_radps,wheel_right_radps,motor_left_duty,motor_left_mode,motor_right_duty,motor_right_mode");
}

// firmware_examples/lib/README.md lists every function the drivers' headers declare, as `name(`,
// so a driver that gains a call cannot leave its page behind.
TEST(Docs, TheDriversPageListsEveryCallTheirHeadersDeclare) {
  const std::filesystem::path lib = std::filesystem::path(SEAR_ASSET_DIR) / ".." / "firmware_examples" / "lib";
  const std::string page = read_file((lib / "README.md").string());
  const std::regex declaration(R"(^[a-z][\w ]*?\b(\w+)\((?:const |struct |void|uint|int)[^;]*\);)", std::regex::ECMAScript | std::regex::multiline);
  int seen = 0;
  for (const auto& entry : std::filesystem::directory_iterator(lib)) {
    if (entry.path().extension() != ".h") continue;
    const std::string header = read_file(entry.path().string());
    EXPECT_NE(page.find("`" + entry.path().filename().string() + "`"), std::string::npos) << entry.path();
    for (std::sregex_iterator it(header.begin(), header.end(), declaration), end; it != end; ++it) {
      ++seen;
      EXPECT_NE(page.find("`" + (*it)[1].str() + "("), std::string::npos)
          << (*it)[1] << " (" << entry.path().filename().string() << ") is not in lib/README.md";
    }
  }
  EXPECT_GE(seen, 27);  // the 27 calls of the eight headers today: the pattern still finds them
}

// docs/firmware.md's HAL table has a row per header of hal/include/hal/, naming every call the
// header declares (`name(...)` or `name`); and every `name(` in the table is a call some header
// declares, so that neither the page nor the HAL can gain or lose a call alone.
TEST(Docs, TheHalTableNamesEveryCallTheHeadersDeclare) {
  const std::filesystem::path include = std::filesystem::path(SEAR_ASSET_DIR) / ".." / "hal" / "include" / "hal";
  const std::string page = read_file(std::filesystem::path(SEAR_ASSET_DIR) / ".." / "docs" / "firmware.md");
  const std::regex declaration(R"(^[^#/ *][^;{}()]*?\b(\w+)\([^;]*\);)", std::regex::ECMAScript | std::regex::multiline);
  std::set<std::string> declared;
  std::string table;
  for (const auto& entry : std::filesystem::directory_iterator(include)) {
    const std::string header = read_file(entry.path()), name = entry.path().filename().string();
    std::vector<std::string> calls;
    for (std::sregex_iterator it(header.begin(), header.end(), declaration), end; it != end; ++it) calls.push_back((*it)[1]);
    if (calls.empty()) continue;  // hal.h, which includes the others
    const auto row = page.find("\n| `" + name + "` |");
    ASSERT_NE(row, std::string::npos) << "docs/firmware.md's HAL table has no row for " << name;
    const std::string text = page.substr(row, page.find('\n', row + 1) - row);
    table += text;
    for (const std::string& call : calls) {
      declared.insert(call);
      EXPECT_TRUE(text.find("`" + call + "(") != std::string::npos || text.find("`" + call + "`") != std::string::npos)
          << call << " (" << name << ") is not in its row of docs/firmware.md's HAL table";
    }
  }
  EXPECT_GE(declared.size(), 50u);  // the 50 calls of the twelve headers today: the pattern still finds them
  const std::regex named(R"(`(\w+)\()");
  for (std::sregex_iterator it(table.begin(), table.end(), named), end; it != end; ++it)
    EXPECT_TRUE(declared.count((*it)[1])) << "docs/firmware.md's HAL table names " << (*it)[1] << "(), which no header declares";
}

}  // namespace
}  // namespace sear::test
