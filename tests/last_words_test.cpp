// A firmware's last words: bytes it had queued on a UART when it stopped (however it stopped) or
// when the run ended never reach the wire, as on the chip, but the console log ends with them on
// lines marked "[never sent]", the line cut short says so, and summary.json carries them per port.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "firmware_run.hpp"

namespace sear::test {
namespace {

// What late_bytes_probe.c queues at 1200 baud: 82 bytes, 10 bits each.
const std::string kText = "0123456789012345678901234567890123456789\n0123456789012345678901234567890123456789\n";
constexpr double kByteS = 10.0 / 1200;

std::string one_mcu(const char* executable) {
  return std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + executable + "\"/>\n    </mcu>\n";
}

struct Stop {
  const char* executable;
  const char* kind;  // summary.json's mcu_stops[0].kind
  const char* options;
};
void PrintTo(const Stop& s, std::ostream* os) { *os << s.kind << " " << s.options; }

// The console's lines as "[never sent] ..." and the rest.
struct Console {
  std::string sent;        // what left, line ends restored
  std::string never_sent;  // what the marked lines hold, line ends restored
  std::string cut_marker;  // the marker on a line cut short, empty if none
};

Console read_console(const std::string& log) {
  Console c;
  for (const auto& line : lines_of(log)) {
    const std::string text = line.substr(line.find(' ') + 1);  // after the time stamp
    const std::string never = "[never sent] ";
    const auto cut = text.find(" [line not ended: ");
    if (text.rfind(never, 0) == 0) c.never_sent += text.substr(never.size()) + "\n";
    else if (cut != std::string::npos) {
      c.sent += text.substr(0, cut);
      c.cut_marker = text.substr(cut + 1);
    } else c.sent += text + "\n";
  }
  return c;
}

class LastWords : public ::testing::TestWithParam<Stop> {};

// Each stop comes 20 ms after the text was queued. Only 66 bytes fit the UART (64 in its ring, one
// in the data register, one shifting), so the call waited for the first 16 to leave (133.3 ms);
// 20 ms later, 153.3 ms (plus a few 3.125 us calls) after the first began, 18 bytes had left: the
// 18th ended at 150.0 ms and the 19th would have at 158.3 ms. The other 64 never left.
TEST_P(LastWords, TheConsoleEndsWithWhatWasNeverSent) {
  const Stop stop = GetParam();
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project(one_mcu(stop.executable), "", 1.0), stop.options);
  EXPECT_EQ(run.exit_code, 3) << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  ASSERT_EQ(summary["mcu_stops"].size(), 1u) << run.err;
  const auto& s = summary["mcu_stops"][0];
  EXPECT_EQ(s["kind"], stop.kind);
  const double stopped_s = s["sim_time_s"].get<double>();
  EXPECT_NEAR(stopped_s, 16 * kByteS + 0.020, 1e-4);  // a few calls of 3.125 us past it

  const Console c = read_console(run.file("rover.main.console.log"));
  EXPECT_EQ(c.sent, kText.substr(0, 18));
  EXPECT_EQ(c.never_sent, kText.substr(18));
  EXPECT_EQ(c.cut_marker, "[line not ended: the MCU stopped]");
  EXPECT_EQ(s["never_sent"]["uart0"], kText.substr(18));
  EXPECT_EQ(run.file("rover.main.uart0.tx.bin"), kText.substr(0, 18));  // the wire stays faithful
  ASSERT_EQ(summary["never_sent"].size(), 1u);
  EXPECT_EQ(summary["never_sent"][0]["bytes"], 64);
  EXPECT_EQ(summary["never_sent"][0]["why"], "mcu stopped");
  // The echo on standard output says the same.
  EXPECT_NE(run.out.find("rover.main: [never sent] 0123456789012345678901234567890123456789"), std::string::npos)
      << run.out;
}

INSTANTIATE_TEST_SUITE_P(EveryWayToStop, LastWords,
                         ::testing::Values(Stop{LATE_CRASH_PROBE, "crashed", "--keep-going"},
                                           Stop{LATE_EXIT_PROBE, "exited", ""},
                                           Stop{LATE_ABORT_PROBE, "crashed", ""},
                                           Stop{LATE_OVERFLOW_PROBE, "crashed", ""},
                                           Stop{LATE_IRQOFF_PROBE, "hung", "--hang-timeout 0.5"}),
                         case_name<Stop>);

// A run of 0.3 s ends with the text still leaving: the bytes that ended by 0.3 s left (the first
// began a few calls after 0, so the 36th ends just past 0.3 s: 35), the rest are marked as cut by
// the run's end, and the summary lists them with no MCU stop.
TEST(LastWords, ARunThatEndsMidLineSaysSo) {
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project(one_mcu(LATE_WAIT_PROBE), "", 0.3), "");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  const Console c = read_console(run.file("rover.main.console.log"));
  EXPECT_EQ(c.sent, kText.substr(0, 35));
  EXPECT_EQ(c.never_sent, kText.substr(35));
  EXPECT_EQ(c.cut_marker, "[line not ended: the run ended]");
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_TRUE(summary["mcu_stops"].empty());
  ASSERT_EQ(summary["never_sent"].size(), 1u);
  EXPECT_EQ(summary["never_sent"][0]["why"], "run ended");
  EXPECT_EQ(summary["never_sent"][0]["text"], kText.substr(35));
  EXPECT_DOUBLE_EQ(summary["never_sent"][0]["time_s"].get<double>(), 0.3);
}

}  // namespace
}  // namespace sear::test
