// Expectations of a headless run: loading <scenario> files and their errors, the verdict of each
// kind at the right sim time from synthetic events and world moments, and the JUnit report
// (parsed back with tinyxml2, checked by libxml2's xmllint, merged from shards).
#include <gtest/gtest.h>
#include <tinyxml2.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "expect/expectation_checker.hpp"
#include "expect/junit_report.hpp"
#include "expect/scenario_loader.hpp"
#include "runtime/simulation.hpp"
#include "scene/project_loader.hpp"

namespace sear {
namespace {

namespace fs = std::filesystem;

constexpr std::int64_t kMs = 1000000;
constexpr std::int64_t kS = 1000000000;

fs::path temp_dir() {
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("sear_expect_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

// The folder goes when the tests end.
struct RemoveTempDir : ::testing::Environment {
  void TearDown() override { if (!std::getenv("KEEP")) fs::remove_all(temp_dir()); }
};
const auto* const kRemoveTempDir = ::testing::AddGlobalTestEnvironment(new RemoveTempDir);

void write(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A rover with one MCU: its console on UART0 (the default) and a u-blox GPS on UART3; a crate and
// an oak to bump into.
const fs::path& project_file() {
  static const fs::path path = [] {
    const fs::path p = temp_dir() / "arena.xml";
    write(p, std::string(R"(<project name="arena">
  <run duration="10" seed="3"/>
  <world>
    <box name="crate" pos="3 0" size="0.5 0.5 0.4"/>
    <tree name="oak" pos="-3 -3"/>
  </world>
  <robot file=")") + SEAR_ASSET_DIR + R"(/robots/rover.xml">
    <pose x="0" y="0" yaw_deg="0"/>
    <mcu name="main">
      <firmware executable="/bin/true"/>
      <ublox_neo6m name="gps" uart="3" pos="0 0 0.1"/>
    </mcu>
  </robot>
</project>
)");
    return p;
  }();
  return path;
}

const ProjectDesc& project() {
  static const ProjectDesc desc = [] {
    Diagnostics d;
    auto p = load_project(project_file().string(), d);
    if (!p) throw std::runtime_error(d.joined());
    return *p;
  }();
  return desc;
}

// A scenario on the arena from its <expect> body; fails the test on any load or name error.
Scenario scenario(const std::string& expect, const std::string& scenario_attributes = "timeout=\"60\"") {
  project_file();  // written on first use
  const std::string xml = "<scenario name=\"test\" project=\"arena.xml\" " + scenario_attributes + ">\n<expect>\n" +
                          expect + "\n</expect>\n</scenario>\n";
  Diagnostics d;
  auto s = load_scenario_text(xml, (temp_dir() / "test.scenario.xml").string(), d);
  EXPECT_TRUE(s) << d.joined();
  if (!s) return {};
  EXPECT_TRUE(check_scenario(*s, project(), d)) << d.joined();
  return *s;
}

sear_event event(std::uint8_t kind, std::uint8_t index, std::uint32_t value, std::int64_t time_ns) {
  sear_event e{};
  e.time_ns = time_ns;
  e.kind = kind;
  e.index = index;
  e.value = value;
  return e;
}

// `text` sent by MCU 0 on `port` from `start_ns` on at `baud`, 8N1: each byte is stamped with the
// end of its stop bit, 10 bit times after the one before. Returns the last byte's time.
std::int64_t send(ExpectationChecker& c, std::uint8_t port, const std::string& text, std::int64_t start_ns,
                  std::uint32_t baud = 9600) {
  std::int64_t t = start_ns;
  for (unsigned char b : text) {
    t += serial_frame_ns(baud);
    c.on_mcu_event(0, event(SEAR_EVENT_UART_TX, port, b, t));
  }
  return t;
}

// The world stepping from `from_ns` (exclusive) to `to_ns` in 1 ms steps, the robot at `xy`.
void world(ExpectationChecker& c, std::int64_t from_ns, std::int64_t to_ns, Eigen::Vector2d xy = {0, 0}) {
  for (std::int64_t t = from_ns + kMs; t <= to_ns; t += kMs) c.advance({t, {xy}, {}});
}

const ExpectationResult& result(const ExpectationChecker& c, const std::string& name) {
  for (const auto& r : c.results())
    if (r.expectation->name == name) return r;
  throw std::runtime_error("no expectation named " + name);
}

TEST(ScenarioLoad, ReadsEveryKindWithItsDefaultName) {
  const Scenario s = scenario(R"(
    <console mcu="rover.main" matches="wp 4/4 reached" before="50"/>
    <console mcu="rover.main" never="fault|panic"/>
    <region robot="rover" shape="circle" center="5 5" radius="1" before="30"/>
    <region robot="rover" shape="box" min="-1 -1" max="1 1"/>
    <no_collision robot="rover" with="crate"/>
    <pin mcu="rover.main" pin="13" level="1" at="2.5"/>
    <pin mcu="rover.main" pin="13" level="0" from="1" to="2" name="led off"/>
    <uart mcu="rover.main" port="1" direction="tx" at_least="100"/>
    <uart mcu="rover.main" port="3" direction="rx" contains="$GPGGA" before="10"/>
    <uart mcu="rover.main" port="1" direction="tx" hex="B5 62 06"/>
    <mcu_running mcu="rover.main"/>)",
                              "seed=\"7\" timeout=\"60\"");
  EXPECT_EQ(s.name, "test");
  EXPECT_EQ(s.seed, 7u);
  EXPECT_EQ(s.timeout_ns, 60 * kS);
  EXPECT_EQ(s.project_file, fs::absolute(project_file()).lexically_normal().string());
  ASSERT_EQ(s.expectations.size(), 11u);
  const std::vector<std::string> names = {
      "console rover.main matches \"wp 4/4 reached\" before 50 s",
      "console rover.main never \"fault|panic\"",
      "region rover circle (5, 5) r 1 before 30 s",
      "region rover box (-1, -1)..(1, 1)",
      "no collision rover with crate",
      "pin rover.main 13 is 1 at 2.5 s",
      "led off",
      "uart rover.main port 1 tx at least 100 bytes",
      "uart rover.main port 3 rx contains \"$GPGGA\" before 10 s",
      "uart rover.main port 1 tx contains B5 62 06",
      "mcu rover.main keeps running"};
  for (std::size_t i = 0; i < names.size(); ++i) EXPECT_EQ(s.expectations[i].name, names[i]);
  EXPECT_EQ(s.expectations[0].before_ns, 50 * kS);
  EXPECT_EQ(s.expectations[0].source.line, 4);  // the <scenario> and <expect> lines, a blank line, then it
  const auto& pin = std::get<PinExpect>(s.expectations[6].what);
  EXPECT_EQ(pin.from_ns, 1 * kS);
  EXPECT_EQ(pin.to_ns, 2 * kS);
  EXPECT_EQ(std::get<UartExpect>(s.expectations[9].what).pattern, std::string("\xB5\x62\x06"));

  // A project's own <expect>, with its timeout there; a project without one checks nothing.
  Diagnostics d;
  const auto own = load_scenario_text(R"(<project name="p"><expect timeout="5"><mcu_running mcu="rover.main"/></expect></project>)",
                                      (temp_dir() / "p.xml").string(), d);
  ASSERT_TRUE(own) << d.joined();
  EXPECT_EQ(own->name, "p");
  EXPECT_EQ(own->timeout_ns, 5 * kS);
  EXPECT_EQ(own->expectations.size(), 1u);
  const auto none = load_scenario(project_file().string(), d);
  ASSERT_TRUE(none) << d.joined();
  EXPECT_EQ(none->name, "arena");
  EXPECT_TRUE(none->expectations.empty());
}

TEST(ScenarioLoad, ErrorsNameFileLineAndTheNearestName) {
  project_file();  // written on first use
  const std::string path = (temp_dir() / "broken.scenario.xml").string();
  const std::string xml = R"(<scenario name="broken" project="arena.xml" timeout="20">
  <expect>
    <console mcu="rover.main" matches="a" never="b"/>
    <console mcu="rover.main" matches="(unclosed"/>
    <region robot="rover" shape="box" min="0 0"/>
    <pin mcu="rover.main" pin="70" level="1" at="1"/>
    <uart mcu="rover.main" port="1" direction="tz" at_least="3"/>
    <consol mcu="rover.main" never="x"/>
    <mcu_running mcu="rover.main" nmae="x"/>
    <console mcu="rover.main" matches="late" before="30"/>
  </expect>
</scenario>
)";
  Diagnostics d;
  EXPECT_FALSE(load_scenario_text(xml, path, d));
  const auto has = [&](int line, const std::string& text) {
    for (const auto& e : d.all())
      if (e.file == path && e.line == line && e.message.find(text) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(has(3, "exactly one of 'matches' or 'never'")) << d.joined();
  EXPECT_TRUE(has(4, "not an ECMAScript regular expression")) << d.joined();
  EXPECT_TRUE(has(5, "needs attribute 'max'")) << d.joined();
  EXPECT_TRUE(has(6, "70 is out of range (expected 0..69")) << d.joined();
  EXPECT_TRUE(has(7, "'tz' is not one of tx, rx (did you mean 'tx'?)")) << d.joined();
  EXPECT_TRUE(has(8, "unknown element <consol> in <expect> (did you mean 'console'?)")) << d.joined();
  EXPECT_TRUE(has(9, "unknown attribute 'nmae' on <mcu_running> (did you mean 'name'?)")) << d.joined();
  EXPECT_TRUE(has(10, "after the timeout")) << d.joined();
  EXPECT_EQ(d.count(), 8u) << d.joined();

  // Names are checked against the loaded project.
  Diagnostics names;
  const auto s = load_scenario_text(R"(<scenario project="arena.xml">
  <expect>
    <console mcu="rover.mian" never="x"/>
    <region robot="rovr" shape="circle" center="0 0" radius="1"/>
    <no_collision robot="rover" with="crat"/>
    <mcu_running mcu="main"/>
  </expect>
</scenario>)",
                                    path, names);
  ASSERT_TRUE(s) << names.joined();
  EXPECT_EQ(s->name, "broken.scenario");  // the file's stem
  EXPECT_FALSE(check_scenario(*s, project(), names));
  ASSERT_EQ(names.count(), 4u) << names.joined();
  EXPECT_EQ(names.all()[0].str(), path + ":3: error: <console> mcu 'rover.mian': the project has no such MCU "
                                         "(did you mean 'rover.main'?)");
  EXPECT_NE(names.all()[1].message.find("robot 'rovr': the project has no such robot (did you mean 'rover'?)"),
            std::string::npos);
  EXPECT_NE(names.all()[2].message.find("with 'crat': the project has no such obstacle or robot (did you mean 'crate'?)"),
            std::string::npos);
  EXPECT_NE(names.all()[3].message.find("MCUs are named 'robot.mcu'"), std::string::npos);
}

// 9600 baud 8N1: a byte takes 10 bit times, 1.041667 ms, so a 15-byte line written at 10 ms ends
// on the line at 10 + 15 x 1.041667 = 25.625 ms, though the firmware reports all of it within
// its quantum [10, 11) ms: the verdicts go by the bytes' times, and wait until the world gets there.
TEST(ExpectationChecker, ConsoleLinesGoByTheirBytesTimes) {
  const Scenario s = scenario(R"(
    <console mcu="rover.main" matches="wp 4/4 reached" before="0.025" name="too early"/>
    <console mcu="rover.main" matches="^wp \d/4 reached$" before="0.026" name="in time"/>
    <console mcu="rover.main" never="fault|panic" name="no fault"/>)");
  ExpectationChecker c(s, project());
  const std::int64_t frame = serial_frame_ns(9600);
  ASSERT_EQ(frame, 1041667);
  const std::int64_t end = send(c, 0, "wp 4/4 reached\n", 10 * kMs);
  EXPECT_EQ(end, 10 * kMs + 15 * frame);
  world(c, 0, 20 * kMs);
  EXPECT_EQ(result(c, "too early").verdict, Verdict::Pending);
  EXPECT_EQ(result(c, "in time").verdict, Verdict::Pending);
  world(c, 20 * kMs, 30 * kMs);
  EXPECT_EQ(result(c, "too early").verdict, Verdict::Failed);
  EXPECT_EQ(result(c, "too early").time_ns, 25 * kMs);
  EXPECT_EQ(result(c, "too early").seen, "no console line by 0.025 s");
  EXPECT_EQ(result(c, "in time").verdict, Verdict::Passed);
  EXPECT_EQ(result(c, "in time").time_ns, end);
  EXPECT_FALSE(c.decided());

  // '\r' is dropped, as console.log drops it; the line is stamped with its '\n'.
  const std::int64_t fault = send(c, 0, "motor fault 3\r\n", 40 * kMs);
  world(c, 30 * kMs, 60 * kMs);
  EXPECT_EQ(result(c, "no fault").verdict, Verdict::Failed);
  EXPECT_EQ(result(c, "no fault").time_ns, fault);
  EXPECT_EQ(result(c, "no fault").seen, "line 'motor fault 3' at 0.056 s");
  EXPECT_TRUE(c.decided());
  EXPECT_FALSE(c.passed());
  EXPECT_EQ(failure_text(result(c, "no fault")), "expectation failed at 0.056 s: no fault: line 'motor fault 3' at 0.056 s");
}

// A firmware that prints 20 000 bytes without a newline: std::regex's recursion would overflow
// the stack on such a line (between 8 and 12 KiB for this pattern), so lines are matched on their
// first 4 KiB, and the 'c' at the end is not seen.
TEST(ExpectationChecker, LongLinesAreMatchedOnTheirFirst4KiB) {
  const Scenario s = scenario(R"(<console mcu="rover.main" never="^(a|b)*c" name="no c"/>)", "timeout=\"1\"");
  ExpectationChecker c(s, project());
  send(c, 0, std::string(20000, 'a') + "c\n", 0, 2000000);
  c.finish(1 * kS);
  EXPECT_EQ(result(c, "no c").verdict, Verdict::Passed);
}

// The robot drives east at 1 m/s from the origin, sampled at 100 ms steps.
TEST(ExpectationChecker, RegionsReachedInTimeOrNot) {
  const Scenario s = scenario(R"(
    <region robot="rover" shape="circle" center="5 0" radius="1" before="4.5" name="east"/>
    <region robot="rover" shape="circle" center="5 5" radius="1" before="3" name="north-east"/>
    <region robot="rover" shape="box" min="-1 -1" max="1 1" name="start"/>
    <region robot="rover" shape="box" min="6 -1" max="7 1" name="far"/>)",
                              "timeout=\"8\"");
  ExpectationChecker c(s, project());
  for (std::int64_t t = 100 * kMs; t <= 10 * kS && !c.decided(); t += 100 * kMs)
    c.advance({t, {{static_cast<double>(t) / kS, 0.0}}, {}});
  EXPECT_EQ(result(c, "start").verdict, Verdict::Passed);
  EXPECT_EQ(result(c, "start").time_ns, 100 * kMs);
  EXPECT_EQ(result(c, "east").verdict, Verdict::Passed);
  EXPECT_EQ(result(c, "east").time_ns, 4 * kS);  // x = 4 m: 1 m from (5, 0)
  // At 3 s the robot is at (3, 0), sqrt(2^2 + 5^2) = 5.385 m from (5, 5), the closest it came.
  EXPECT_EQ(result(c, "north-east").verdict, Verdict::Failed);
  EXPECT_EQ(result(c, "north-east").time_ns, 3 * kS);
  EXPECT_EQ(result(c, "north-east").seen, "the robot came no closer than 5.39 m to (5, 5), at 3.000 s");
  // Reached at 6 s, before the timeout.
  EXPECT_EQ(result(c, "far").verdict, Verdict::Passed);
  EXPECT_EQ(result(c, "far").time_ns, 6 * kS);
  EXPECT_TRUE(c.decided());  // at 6 s: the run may stop there

  // The same far box with the robot stopped at x = 4.5 m: 1.5 m short of its edge at the timeout.
  ExpectationChecker stuck(s, project());
  for (std::int64_t t = 100 * kMs; t <= 9 * kS; t += 100 * kMs)
    stuck.advance({t, {{std::min(4.5, static_cast<double>(t) / kS), 0.0}}, {}});
  EXPECT_EQ(result(stuck, "far").verdict, Verdict::Failed);
  EXPECT_EQ(result(stuck, "far").time_ns, 8 * kS);
  EXPECT_EQ(result(stuck, "far").seen, "the robot came no closer than 1.50 m to the box, at 4.500 s");
}

TEST(ExpectationChecker, CollisionsWithAnythingOrOneObstacle) {
  const Scenario s = scenario(R"(
    <no_collision robot="rover" name="nothing"/>
    <no_collision robot="rover" with="crate" name="crate"/>
    <no_collision robot="rover" with="oak" name="oak"/>)",
                              "timeout=\"5\"");
  ExpectationChecker c(s, project());
  world(c, 0, 1 * kS);
  // A robot that hits this one names it as the other.
  c.advance({1 * kS + kMs, {{0, 0}}, {{1 * kS + kMs, "car", "rover"}}});
  world(c, 1 * kS + kMs, 2 * kS);
  c.advance({2 * kS + kMs, {{0, 0}}, {{2 * kS + kMs, "rover", "crate"}}});
  EXPECT_EQ(result(c, "nothing").verdict, Verdict::Failed);
  EXPECT_EQ(result(c, "nothing").seen, "touched 'car' at 1.001 s");
  EXPECT_EQ(result(c, "crate").verdict, Verdict::Failed);
  EXPECT_EQ(result(c, "crate").time_ns, 2 * kS + kMs);
  EXPECT_EQ(result(c, "crate").seen, "touched 'crate' at 2.001 s");
  EXPECT_EQ(result(c, "oak").verdict, Verdict::Pending);
  world(c, 2 * kS + kMs, 5 * kS);
  EXPECT_EQ(result(c, "oak").verdict, Verdict::Passed);
  EXPECT_EQ(result(c, "oak").time_ns, 5 * kS);
  EXPECT_TRUE(c.decided());
}

// Pin 13: an output driven 1 at 1 s (mode and level at one instant), 0 at 3 s, PWM from 4 s.
TEST(ExpectationChecker, PinLevelsAtInstantsAndOverIntervals) {
  const Scenario s = scenario(R"(
    <pin mcu="rover.main" pin="13" level="1" at="0.5" name="too soon"/>
    <pin mcu="rover.main" pin="13" level="1" at="1" name="at the switch"/>
    <pin mcu="rover.main" pin="13" level="1" at="2.5" name="high"/>
    <pin mcu="rover.main" pin="13" level="1" from="1" to="3" name="held to 3"/>
    <pin mcu="rover.main" pin="13" level="1" from="2" to="3.5" name="held to 3.5"/>
    <pin mcu="rover.main" pin="13" level="1" at="4.5" name="pwm"/>)");
  ExpectationChecker c(s, project());
  c.on_mcu_event(0, event(SEAR_EVENT_PIN_MODE, 13, 1, 1 * kS));
  c.on_mcu_event(0, event(SEAR_EVENT_PIN, 13, 1, 1 * kS));
  world(c, 0, 2600 * kMs);
  EXPECT_EQ(result(c, "too soon").verdict, Verdict::Failed);
  EXPECT_EQ(result(c, "too soon").seen, "pin 13 was not driven (an input) at 0.500 s");
  EXPECT_EQ(result(c, "at the switch").verdict, Verdict::Passed);
  EXPECT_EQ(result(c, "at the switch").time_ns, 1 * kS);
  EXPECT_EQ(result(c, "high").verdict, Verdict::Passed);
  EXPECT_EQ(result(c, "high").time_ns, 2500 * kMs);
  c.on_mcu_event(0, event(SEAR_EVENT_PIN, 13, 0, 3 * kS));
  c.on_mcu_event(0, event(SEAR_EVENT_PWM, 13, 128, 4 * kS));
  world(c, 2600 * kMs, 5 * kS);
  // The level at 3 s is the one after the change at 3 s: the closed interval [1, 3] ends at 0.
  EXPECT_EQ(result(c, "held to 3").verdict, Verdict::Failed);
  EXPECT_EQ(result(c, "held to 3").seen, "pin 13 was 0 at 3.000 s");
  EXPECT_EQ(result(c, "held to 3.5").verdict, Verdict::Failed);
  EXPECT_EQ(result(c, "held to 3.5").time_ns, 3 * kS);
  EXPECT_EQ(result(c, "pwm").verdict, Verdict::Failed);
  EXPECT_EQ(result(c, "pwm").seen, "pin 13 was a PWM waveform (duty 128/255) at 4.500 s");
}

// The GPS on UART3 puts its bytes on the wire whether or not the firmware reads them; the
// firmware's own RX events for that port repeat them and are not counted again. UART2 has no
// device: its RX events (a capture, a loopback) are what arrives.
TEST(ExpectationChecker, UartBytesCountsAndPatterns) {
  const Scenario s = scenario(R"(
    <uart mcu="rover.main" port="3" direction="rx" contains="$GPGGA" before="0.1" name="gga"/>
    <uart mcu="rover.main" port="3" direction="rx" at_least="20" before="0.1" name="20 from gps"/>
    <uart mcu="rover.main" port="1" direction="tx" hex="B5 62" name="ubx sync"/>
    <uart mcu="rover.main" port="1" direction="tx" at_least="4" name="four"/>
    <uart mcu="rover.main" port="2" direction="rx" at_least="2" name="capture"/>
    <uart mcu="rover.main" port="3" direction="rx" contains="$GPGSV" name="gsv"/>)",
                              "timeout=\"1\"");
  ExpectationChecker c(s, project());
  const std::string nmea = "$GPRMC,1*00\r\n$GPGGA,2*00\r\n";  // 26 bytes
  std::vector<serial_byte> wire;
  std::int64_t t = 0;
  for (unsigned char b : nmea) {
    t += serial_frame_ns(9600);
    wire.push_back({t, 9600, b, {}});
    c.on_mcu_event(0, event(SEAR_EVENT_UART_RX, 3, b, t));
  }
  const std::size_t gps = 0;  // the arena's first device
  c.on_wire_bytes(0, gps, true, wire.data(), wire.size());
  const std::int64_t sync = send(c, 1, "\x01\xB5\x62", 0, 115200);
  c.on_mcu_event(0, event(SEAR_EVENT_UART_RX, 2, 'a', 3 * kMs));
  world(c, 0, 200 * kMs);
  // "$GPGGA" ends with the 19th byte.
  EXPECT_EQ(result(c, "gga").verdict, Verdict::Passed);
  EXPECT_EQ(result(c, "gga").time_ns, 19 * serial_frame_ns(9600));
  EXPECT_EQ(result(c, "20 from gps").time_ns, 20 * serial_frame_ns(9600));
  EXPECT_EQ(result(c, "ubx sync").verdict, Verdict::Passed);
  EXPECT_EQ(result(c, "ubx sync").time_ns, sync);
  EXPECT_EQ(result(c, "four").verdict, Verdict::Pending);
  c.finish(1 * kS);
  EXPECT_EQ(result(c, "four").verdict, Verdict::Failed);
  EXPECT_EQ(result(c, "four").seen, "3 bytes by 1.000 s");
  EXPECT_EQ(result(c, "capture").seen, "1 byte by 1.000 s");
  EXPECT_EQ(result(c, "gsv").verdict, Verdict::Failed);
  EXPECT_EQ(result(c, "gsv").seen, "not among the 26 bytes by 1.000 s");

  // The same 26 bytes with a 27-byte demand: were RX events counted too, it would see 52.
  const Scenario more = scenario(R"(<uart mcu="rover.main" port="3" direction="rx" at_least="27" name="27"/>)",
                                 "timeout=\"1\"");
  ExpectationChecker again(more, project());
  for (const auto& b : wire) again.on_mcu_event(0, event(SEAR_EVENT_UART_RX, 3, b.value, b.end_ns));
  again.on_wire_bytes(0, gps, true, wire.data(), wire.size());
  again.finish(1 * kS);
  EXPECT_EQ(result(again, "27").seen, "26 bytes by 1.000 s");
}

TEST(ExpectationChecker, AnMcuStopDecidesWhatDependsOnIt) {
  const Scenario s = scenario(R"(
    <mcu_running mcu="rover.main" name="running"/>
    <console mcu="rover.main" matches="done" name="done"/>
    <console mcu="rover.main" never="late" name="never late"/>
    <region robot="rover" shape="circle" center="0 0" radius="1" name="home"/>)");
  ExpectationChecker c(s, project());
  send(c, 0, "booted\n", 0, 115200);
  world(c, 0, 5 * kMs);
  // Written just before the crash at 5.2 ms; at 115200 baud the line's last bytes (from 5.26 ms on)
  // would have left after it: they never got out, and the check, as console.log, never sees them,
  // though the firmware reported them within the step before its stop was known.
  send(c, 0, "late\n", 5 * kMs, 115200);
  world(c, 5 * kMs, 6 * kMs);
  c.mcu_stopped("rover.main", 5200000, "crashed with signal 11 (SIGSEGV)");
  EXPECT_EQ(result(c, "running").verdict, Verdict::Failed);
  EXPECT_EQ(result(c, "running").time_ns, 5200000);
  EXPECT_EQ(result(c, "running").seen, "crashed with signal 11 (SIGSEGV) at 0.005 s");
  // What it sent before the stop, "la", ends the console as its last line.
  EXPECT_EQ(result(c, "done").seen,
            "the MCU stopped at 0.005 s (crashed with signal 11 (SIGSEGV)): no line matched among 2 by 0.005 s; "
            "the last: 'la' at 0.005 s");
  EXPECT_EQ(result(c, "never late").verdict, Verdict::Passed);
  EXPECT_EQ(result(c, "home").verdict, Verdict::Passed);  // the robot starts there
  EXPECT_TRUE(c.decided());
}

TEST(ExpectationChecker, PendingExpectationsFailAtTheTimeoutOrTheEnd) {
  const Scenario s = scenario(R"(
    <console mcu="rover.main" matches="ready" name="ready"/>
    <console mcu="rover.main" never="fault" name="no fault"/>
    <mcu_running mcu="rover.main" name="running"/>
    <no_collision robot="rover" name="no collision"/>)",
                              "timeout=\"0.02\"");
  ExpectationChecker c(s, project());
  world(c, 0, 20 * kMs);
  EXPECT_FALSE(c.decided());  // events at 20 ms could still come
  world(c, 20 * kMs, 22 * kMs);
  EXPECT_TRUE(c.decided());
  EXPECT_EQ(result(c, "ready").verdict, Verdict::Failed);
  EXPECT_EQ(result(c, "ready").time_ns, 20 * kMs);
  EXPECT_EQ(result(c, "ready").seen, "no console line by 0.020 s");
  for (const char* name : {"no fault", "running", "no collision"}) {
    EXPECT_EQ(result(c, name).verdict, Verdict::Passed) << name;
    EXPECT_EQ(result(c, name).time_ns, 20 * kMs) << name;
  }

  // A run that ends before the timeout, in the middle of a line: only complete lines are judged,
  // so the fragment neither satisfies nor breaks anything.
  ExpectationChecker early(s, project());
  send(early, 0, "fault without newline", 0, 115200);
  world(early, 0, 3 * kMs);
  early.finish(3 * kMs);
  EXPECT_EQ(result(early, "ready").time_ns, 3 * kMs);
  EXPECT_EQ(result(early, "ready").seen, "no console line by 0.003 s");
  EXPECT_EQ(result(early, "no fault").verdict, Verdict::Passed);
  EXPECT_EQ(result(early, "no fault").time_ns, 3 * kMs);
  EXPECT_EQ(result(early, "running").verdict, Verdict::Passed);
  EXPECT_EQ(result(early, "running").time_ns, 3 * kMs);
}

// An interrupted run (Ctrl-C, a viewer closed before Start) decides only what was due by its end:
// what it met passes, what fell due fails, and the rest stays undecided rather than failed.
TEST(ExpectationChecker, AnInterruptedRunLeavesWhatWasNotYetDueUndecided) {
  const Scenario s = scenario(R"(
    <console mcu="rover.main" matches="ready" name="ready"/>
    <console mcu="rover.main" matches="boot" before="0.002" name="boot"/>
    <console mcu="rover.main" matches="said" name="said"/>
    <console mcu="rover.main" never="fault" name="no fault"/>)",
                              "timeout=\"0.02\"");
  ExpectationChecker c(s, project());
  send(c, 0, "said\n", 0, 115200);  // 5 bytes at 86.8 us: on the wire by 0.43 ms
  world(c, 0, 3 * kMs);
  c.finish(3 * kMs, true);
  EXPECT_EQ(result(c, "said").verdict, Verdict::Passed);
  EXPECT_EQ(result(c, "boot").verdict, Verdict::Failed);  // due at 2 ms, before the interruption
  EXPECT_EQ(result(c, "boot").time_ns, 2 * kMs);
  EXPECT_EQ(result(c, "ready").verdict, Verdict::Pending);     // due at the 20 ms timeout
  EXPECT_EQ(result(c, "no fault").verdict, Verdict::Pending);  // watched until then
}

// The world's own steps: the rover rests at its start pose.
TEST(ExpectationChecker, WatchesASimulation) {
  const Scenario s = scenario(R"(
    <region robot="rover" shape="box" min="-0.5 -0.5" max="0.5 0.5" name="start"/>
    <region robot="rover" shape="circle" center="5 5" radius="1" before="0.05" name="far"/>)");
  Simulation sim(project(), 1);
  ExpectationChecker c(s, project());
  while (!c.decided()) {
    sim.step();
    c.on_step(sim);
  }
  EXPECT_EQ(result(c, "start").time_ns, sim.step_ns());
  EXPECT_EQ(result(c, "far").time_ns, 50 * kMs);
  // From about the origin to (5, 5): 5 sqrt(2) = 7.07 m, give or take the few mm the rover settles.
  EXPECT_EQ(result(c, "far").seen.substr(0, 36), "the robot came no closer than 7.07 m");
}

// ---- JUnit ----

JunitSuite failing_suite(const std::string& name, std::uint64_t seed) {
  const Scenario s = scenario(R"(
    <console mcu="rover.main" matches="wp 4/4 reached" before="0.01"/>
    <mcu_running mcu="rover.main"/>)",
                              "timeout=\"0.02\"");
  ExpectationChecker c(s, project());
  send(c, 0, "wp 1/4 <ok> & \"fine\"\n", 0, 115200);
  world(c, 0, 20 * kMs);
  c.finish(20 * kMs);
  // A console log with a byte XML cannot hold (ESC) and one that is not UTF-8.
  JunitSuite suite = junit_suite(s, seed, c, 20 * kMs, "0.000173611 wp 1/4 <ok>\n0.001 \x1b[31mred\xff\n");
  suite.scenario = name;
  return suite;
}

TEST(JunitReport, OneTestCasePerExpectationWithFailuresAndConsole) {
  const fs::path file = temp_dir() / "one.junit.xml";
  JunitSuite broken;
  broken.scenario = "broken";
  broken.seed = 1;
  broken.error = "firmware did not build: rover.c:12: error";
  write_junit(file.string(), {failing_suite("reaches the room", 7), broken});

  tinyxml2::XMLDocument doc;
  ASSERT_EQ(doc.LoadFile(file.string().c_str()), tinyxml2::XML_SUCCESS);
  const auto* root = doc.RootElement();
  ASSERT_STREQ(root->Name(), "testsuites");
  EXPECT_EQ(root->IntAttribute("tests"), 3);
  EXPECT_EQ(root->IntAttribute("failures"), 1);
  EXPECT_EQ(root->IntAttribute("errors"), 1);
  EXPECT_STREQ(root->Attribute("time"), "0.020");  // the runs' lengths: 0 and 20 ms
  // Ordered by scenario name: "broken" first.
  const auto* first = root->FirstChildElement("testsuite");
  ASSERT_TRUE(first);
  EXPECT_STREQ(first->Attribute("name"), "broken (seed 1)");
  EXPECT_STREQ(first->FirstChildElement("testcase")->FirstChildElement("error")->Attribute("message"),
               "firmware did not build: rover.c:12: error");
  const auto* suite = first->NextSiblingElement("testsuite");
  ASSERT_TRUE(suite);
  EXPECT_STREQ(suite->Attribute("name"), "reaches the room (seed 7)");
  EXPECT_EQ(suite->IntAttribute("tests"), 2);
  EXPECT_EQ(suite->IntAttribute("failures"), 1);
  EXPECT_EQ(suite->IntAttribute("errors"), 0);
  EXPECT_STREQ(suite->Attribute("time"), "0.020");
  std::map<std::string, std::string> properties;
  for (auto* p = suite->FirstChildElement("properties")->FirstChildElement("property"); p;
       p = p->NextSiblingElement("property"))
    properties[p->Attribute("name")] = p->Attribute("value");
  EXPECT_EQ(properties["seed"], "7");
  EXPECT_EQ(properties["project"], fs::absolute(project_file()).lexically_normal().string());
  const auto* console = suite->FirstChildElement("testcase");
  EXPECT_STREQ(console->Attribute("classname"), "reaches the room");
  EXPECT_STREQ(console->Attribute("name"), "console rover.main matches \"wp 4/4 reached\" before 0.01 s");
  EXPECT_STREQ(console->Attribute("time"), "0.010");
  const auto* failure = console->FirstChildElement("failure");
  ASSERT_TRUE(failure);
  EXPECT_STREQ(failure->Attribute("type"), "expectation");
  EXPECT_STREQ(failure->Attribute("message"),
               "no line matched among 1 by 0.010 s; the last: 'wp 1/4 <ok> & \"fine\"' at 0.002 s");
  EXPECT_NE(std::string(failure->GetText()).find("expectation failed at 0.010 s: console rover.main"), std::string::npos);
  EXPECT_NE(std::string(failure->GetText()).find("test.scenario.xml:4"), std::string::npos);
  const auto* running = console->NextSiblingElement("testcase");
  EXPECT_FALSE(running->FirstChildElement("failure"));
  EXPECT_STREQ(running->Attribute("time"), "0.020");
  // ESC and the stray 0xFF became U+FFFD; the rest is the log as given.
  EXPECT_STREQ(suite->FirstChildElement("system-out")->GetText(),
               "0.000173611 wp 1/4 <ok>\n0.001 \xEF\xBF\xBD[31mred\xEF\xBF\xBD\n");

  // An independent parser (libxml2) takes it as well-formed XML.
  if (std::system("command -v xmllint >/dev/null 2>&1") != 0) GTEST_SKIP() << "xmllint (libxml2-utils) not installed";
  EXPECT_EQ(std::system(("xmllint --noout '" + file.string() + "'").c_str()), 0);
}

TEST(JunitReport, MergedShardsEqualOneRunsReport) {
  const JunitSuite a = failing_suite("alpha", 2);
  const JunitSuite b = failing_suite("alpha", 10);  // seeds sort as numbers: 2 before 10
  const JunitSuite c = failing_suite("beta", 1);
  const fs::path single = temp_dir() / "single.xml", one = temp_dir() / "shard1.xml", two = temp_dir() / "shard2.xml",
                 merged = temp_dir() / "merged.xml";
  write_junit(single.string(), {c, b, a});
  write_junit(one.string(), {c, a});
  write_junit(two.string(), {b});
  merge_junit({two.string(), one.string()}, merged.string());
  const std::string expected = read(single);
  EXPECT_EQ(read(merged), expected);
  const auto suites = read_junit(single.string());
  ASSERT_EQ(suites.size(), 3u);
  EXPECT_EQ(suites[0].name(), "alpha (seed 2)");
  EXPECT_EQ(suites[1].name(), "alpha (seed 10)");
  EXPECT_EQ(suites[2].name(), "beta (seed 1)");
  EXPECT_THROW(read_junit((temp_dir() / "missing.xml").string()), std::runtime_error);
}

}  // namespace
}  // namespace sear
