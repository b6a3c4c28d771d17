// The ranging examples end to end, as a user runs them: each firmware reads its sensor through
// the real part's wire format (ECHO pulse widths, a MaxBotix's three outputs, LMS telegrams) and
// the numbers it prints are checked against the world's geometry and the datasheets.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>

#include "firmware_run.hpp"
#include "project_text.hpp"

namespace sear::test {
namespace {

const std::filesystem::path kExamples = std::filesystem::path(SEAR_ASSET_DIR) / ".." / "firmware_examples";

// An example's project with its firmware sources and robot named by absolute paths, so that a
// variant can live elsewhere.
std::string example_project(const std::string& name) {
  std::string text = read_file(kExamples / name / "project.xml");
  const std::string key = "sources=\"";
  const auto begin = text.find(key) + key.size();
  const auto end = text.find('"', begin);
  std::istringstream files(text.substr(begin, end - begin));
  std::string absolute;
  for (std::string file; files >> file;)
    absolute += (absolute.empty() ? "" : " ") + (kExamples / name / file).lexically_normal().string();
  text.replace(begin, end - begin, absolute);
  return replaced(text, "file=\"../../assets/robots/rover.xml\"", "file=\"" SEAR_ASSET_DIR "/robots/rover.xml\"");
}

// The rover's x at the end of the run, from its trace: it creeps a millimetre or so while it
// stands (ODE's contacts at 20 solver iterations), which the sonars see.
double final_x(const SearRun& run) {
  const auto rows = lines_of(run.file("trace_rover.csv"));
  double x = 0;
  std::sscanf(rows.back().c_str(), "%*[^,],%lf", &x);
  return x;
}

// The echo widths of a run of the HC-SR04 example in `project`, checked against the wall.
void expect_echoes_of_the_wall(const SearRun& run) {
  // The wall's face is at x = 1.15 m, the sensor 0.15 m ahead of the rover's origin.
  const double distance_cm = (1.15 - (final_x(run) + 0.15)) * 100;
  const double expected_us = 58.0 * distance_cm;  // datasheet: range (cm) = width (us) / 58
  const std::regex ping(R"(ping (\d+): (\d+) us)");
  int pings = 0;
  for (const auto& line : lines_of(run.file("rover.main.console.log"))) {
    EXPECT_EQ(line.find("no echo"), std::string::npos) << line;
    std::smatch m;
    if (!std::regex_search(line, m, ping)) continue;
    ++pings;
    // The model's noise is 1 mm (5.8 us) clipped at 3 sigma, and micros() counts whole
    // microseconds: every width lies within 17.4 + 1 us of the geometry's.
    EXPECT_NEAR(std::stod(m[2]), expected_us, 18.4) << line;
  }
  // A ping every 65 ms (the example's cycle) over 2 s, the first after start-up.
  EXPECT_GE(pings, 28);
}

TEST(Hcsr04Run, EchoWidthsGiveTheWallDistanceToTheDatasheetResolution) {
  TempDir dir;
  const SearRun run = run_sear(dir, example_project("hcsr04_ping"), "--duration 2");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  expect_echoes_of_the_wall(run);
}

// Polled as most sketches do, with digital_read() and micros() in a loop: the echo's edges fall
// due within the quantum of the TRIG pulse that starts it, and the loop sees each at once.
TEST(Hcsr04Run, APolledEchoHasTheWidthOfTheDistance) {
  TempDir dir;
  const std::string mcu = std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + ECHO_POLL_PROBE +
                          "\"/>\n      <hcsr04 name=\"sonar\" trig=\"24\" echo=\"10\" pos=\"0.15 0 0.05\"/>\n    </mcu>\n";
  const std::string wall = "    <wall name=\"target\" from=\"1.2 -2\" to=\"1.2 2\" height=\"0.5\" thickness=\"0.1\"/>\n";
  const SearRun run = run_sear(dir, rover_project(mcu, wall, 1.0));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const double expected_us = 58.0 * (1.15 - (final_x(run) + 0.15)) * 100;
  int echoes = 0;
  for (const auto& line : lines_of(run.file("rover.main.console.log"))) {
    unsigned long width = 0;
    if (std::sscanf(line.c_str(), "%*s echo %lu us", &width) != 1) continue;
    ++echoes;
    // The model's 3-sigma noise (17.4 us) and the loop's sampling: a pass of the loop is two HAL
    // calls, 6.25 us at the default cost, at each edge.
    EXPECT_NEAR(static_cast<double>(width), expected_us, 17.4 + 2 * 6.25) << line;
  }
  EXPECT_GE(echoes, 10);
}

// The levels of pin `pin` in a pins.vcd, as (time, level) changes: pin n's identifier is '!' + n.
std::vector<std::pair<long long, char>> pin_changes(const std::string& vcd, int pin) {
  std::vector<std::pair<long long, char>> changes;
  const std::string id(1, static_cast<char>('!' + pin));
  long long t = 0;
  bool body = false;
  for (const auto& line : lines_of(vcd)) {
    if (line.rfind("$enddefinitions", 0) == 0) body = true;
    if (!body || line.empty()) continue;
    if (line[0] == '#') t = std::stoll(line.substr(1));
    else if (line.size() == 2 && line.substr(1) == id) changes.emplace_back(t, line[0]);
  }
  return changes;
}

// The pins a device drives are in the waveform as a logic analyser would see them: each echo the
// polled firmware timed is a high pulse on ECHO (pin 10) that rises after TRIG (pin 24) fell, as
// wide as the firmware measured to within its loop's sampling. A pass of the loop is a
// digital_read() and a micros(), 2 calls of 3.125 us: the read that sees each edge comes 0 to
// 6.25 us after it, both edges' micros() follow their read by the same call, and micros() counts
// whole microseconds, so the two widths differ by less than 6.25 + 1 us.
TEST(Hcsr04Run, TheEchoADeviceDrivesIsInTheWaveform) {
  TempDir dir;
  const std::string mcu = std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + ECHO_POLL_PROBE +
                          "\"/>\n      <hcsr04 name=\"sonar\" trig=\"24\" echo=\"10\" pos=\"0.15 0 0.05\"/>\n    </mcu>\n";
  const std::string wall = "    <wall name=\"target\" from=\"1.2 -2\" to=\"1.2 2\" height=\"0.5\" thickness=\"0.1\"/>\n";
  const SearRun run = run_sear(dir, rover_project(mcu, wall, 0.5));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::vector<unsigned long> timed;
  for (const auto& line : lines_of(run.file("rover.main.console.log"))) {
    unsigned long width = 0;
    if (std::sscanf(line.c_str(), "%*s echo %lu us", &width) == 1) timed.push_back(width);
  }
  const auto echo = pin_changes(run.file("rover.main.pins.vcd"), 10);
  const auto trig = pin_changes(run.file("rover.main.pins.vcd"), 24);
  std::vector<std::pair<long long, long long>> pulses;  // rise, fall
  for (std::size_t k = 0; k + 1 < echo.size(); ++k)
    if (echo[k].second == '1' && echo[k + 1].second == '0') pulses.emplace_back(echo[k].first, echo[k + 1].first);
  ASSERT_GE(timed.size(), 6u);  // one every 70 ms and a few, over 0.5 s
  ASSERT_GE(pulses.size(), timed.size());
  for (std::size_t k = 0; k < timed.size(); ++k) {
    const double width_us = static_cast<double>(pulses[k].second - pulses[k].first) * 1e-3;
    EXPECT_NEAR(static_cast<double>(timed[k]), width_us, 6.25 + 1.0) << "echo " << k;
    // The echo rises after the TRIG pulse that started it has ended.
    long long trig_fell = -1;
    for (const auto& c : trig)
      if (c.second == '0' && c.first < pulses[k].first) trig_fell = c.first;
    EXPECT_GT(trig_fell, 0) << "echo " << k;
  }
}

// The device models run in the firmware's own process, sealed behind the HAL: a firmware that
// names its functions as they do (a likely choice for a driver of the same part) neither clashes
// with them at link time nor takes their place.
TEST(Hcsr04Run, AFirmwareMayNameItsFunctionsAsTheDeviceModelsDo) {
  TempDir dir;
  // (The example's own driver already has an hcsr04_trigger() of its own.)
  std::ofstream(dir.path() / "clash.c") << "#include <stdint.h>\n"
                                           "int hcsr04_take_edge(void *s) { (void)s; return 1; }\n"
                                           "int64_t hcsr04_next_edge_ns(const void *s) { (void)s; return 0; }\n"
                                           "double noise_gaussian(uint64_t s, uint64_t i) { (void)s; (void)i; return 1e9; }\n";
  const std::string ping = (kExamples / "hcsr04_ping" / "hcsr04_ping.c").lexically_normal().string();
  const std::string project = replaced(example_project("hcsr04_ping"), "sources=\"" + ping, "sources=\"clash.c " + ping);
  const SearRun run = run_sear(dir, project, "--duration 2");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  expect_echoes_of_the_wall(run);
}

struct MaxbotixCase {
  double wall_x_m;  // the wall's centre line; its face is 5 cm nearer
  int inches;       // what the part reads with no noise: whole inches, truncated
};

void PrintTo(const MaxbotixCase& c, std::ostream* os) { *os << "wall at x " << c.wall_x_m << " m, " << c.inches << " in"; }

class MaxbotixRun : public testing::TestWithParam<MaxbotixCase> {};

TEST_P(MaxbotixRun, AnalogPulseWidthAndSerialAgreeWithEachOtherAndTheWall) {
  TempDir dir;
  std::string project = example_project("maxbotix_three");
  project = replaced(project, "inverter=\"true\"", "inverter=\"true\" noise=\"0\"");
  project = replaced(project, "from=\"1.2 -2\" to=\"1.2 2\"",
                     "from=\"" + std::to_string(GetParam().wall_x_m) + " -2\" to=\"" +
                         std::to_string(GetParam().wall_x_m) + " 2\"");
  const SearRun run = run_sear(dir, project, "--duration 2");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string want = std::to_string(GetParam().inches);
  int agreeing = 0;
  for (const auto& line : lines_of(run.file("rover.main.console.log"))) {
    if (line.find("analog") == std::string::npos || line.find("--") != std::string::npos) continue;
    // With no noise every cycle reads the same, so whichever cycle each output last showed,
    // all three print the geometry's inches.
    EXPECT_NE(line.find("analog " + want + " in, pw " + want + " in, serial " + want + " in"), std::string::npos)
        << line;
    ++agreeing;
  }
  // First reading 250 ms + a calibration cycle + a cycle after power-up; a line every 250 ms.
  EXPECT_GE(agreeing, 5);
}

// 1.00 m = 39.37 in reads 39; 2.00 m = 78.74 in reads 78.
INSTANTIATE_TEST_SUITE_P(Walls, MaxbotixRun, testing::Values(MaxbotixCase{1.2, 39}, MaxbotixCase{2.2, 78}),
                         case_name<MaxbotixCase>);

TEST(MaxbotixSerial, WithoutAnInverterTheUartReadsFramingGarbage) {
  TempDir dir;
  const std::string project = replaced(example_project("maxbotix_three"), "inverter=\"true\"", "inverter=\"false\"");
  const SearRun run = run_sear(dir, project, "--duration 2");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string console = run.file("rover.main.console.log");
  EXPECT_EQ(console.find("serial 39"), std::string::npos) << console;
  // Bytes do arrive (the line toggles), but none of them is the frame's 'R'.
  int received = 0;
  for (const auto& line : lines_of(run.file("rover.main.uart2.log"))) {
    if (line.find(" rx ") == std::string::npos) continue;
    ++received;
    EXPECT_EQ(line.find(" rx 52"), std::string::npos) << line;
  }
  EXPECT_GT(received, 0);
}

// A baud change is answered at the old rate and takes effect at the answer's last stop bit: a
// host that switches its own port then and asks at once, within the same millisecond, is heard.
TEST(Lms2xxRun, ARequestRightAfterABaudChangeIsHeardAtTheNewRate) {
  TempDir dir;
  const std::string mcu = std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + BAUD_SWITCH_PROBE +
                          "\"/>\n      <lms2xx name=\"lidar\" uart=\"1\" power_up=\"2\"/>\n    </mcu>\n";
  const SearRun run = run_sear(dir, rover_project(mcu, "", 3.0));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.file("rover.main.console.log").find("mode change: 10 bytes, first 06; status at 500k: answered 06"),
            std::string::npos)
      << run.file("rover.main.console.log");
}

TEST(WallFollowerRun, ConsoleIsTheGoldenOneAndTheSameEveryRun) {
  TempDir dir;
  const std::string project = example_project("wall_follower");
  TempDir dir2;
  const SearRun a = run_sear(dir, project, "--duration 15");
  const SearRun b = run_sear(dir2, project, "--duration 15");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const std::string console = a.file("rover.main.console.log");
  EXPECT_EQ(console, b.file("rover.main.console.log"));
  EXPECT_EQ(a.file("rover.main.uart1.log"), b.file("rover.main.uart1.log"));
  // Regenerate after a deliberate change with the line below; review the difference first.
  // cp OUT/rover.main.console.log tests/data/wall_follower.console.log
  EXPECT_EQ(console, read_file(std::filesystem::path(SEAR_TEST_DATA) / "wall_follower.console.log"));
  const auto summary = nlohmann::json::parse(a.file("summary.json"));
  EXPECT_EQ(summary["robots"][0]["collisions"].get<int>(), 0);
  EXPECT_GT(summary["robots"][0]["distance_m"].get<double>(), 2.0);
}

}  // namespace
}  // namespace sear::test
