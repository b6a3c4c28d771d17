// Sketches run by `sear` from their folders: the HC-SR04 example reads the wall's distance, and what
// the layer cannot model stops the MCU with a message naming the call.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "firmware_run.hpp"
#include "model_run.hpp"

using namespace sear::test;

namespace {

// `sear run` on a project file where it lies (its relative paths stay valid).
SearRun run_project(const TempDir& dir, const std::string& project, const std::string& extra = "") {
  const auto out = dir.path() / "out";
  const std::string cmd = std::string(SEAR_BINARY) + " run " + project + " " + extra + " -o " + out.string() + " >" +
                          (dir.path() / "stdout").string() + " 2>" + (dir.path() / "stderr").string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_file(dir.path() / "stdout"),
          read_file(dir.path() / "stderr"), out};
}

// The wall's face is 1.00 m from the sensor: Arduino's ping arithmetic (us / 29 / 2, truncated)
// gives 99 or 100 cm within the model's 3 mm noise; every line within a centimetre of 100.
TEST(SonarSketch, ReportsTheWallWithinACentimetre) {
  TempDir dir;
  const SearRun run = run_project(dir, std::string(SEAR_EXAMPLES_DIR) + "/arduino/sonar_sketch/project.xml");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  int readings = 0;
  for (const auto& line : lines_of(run.file("rover.main.console.log"))) {
    long us = 0, cm = 0;
    if (std::sscanf(line.c_str(), "%*s %ld us, %ld cm", &us, &cm) != 2) continue;
    ++readings;
    EXPECT_NEAR(static_cast<double>(cm), 100.0, 1.0) << line;
    EXPECT_NEAR(static_cast<double>(us), 5800.0, 17.4 + 1) << line;  // 3-sigma noise, rounding
  }
  EXPECT_GE(readings, 15);  // one per ~106 ms over 2 s
}

// The fixes a $GPGGA sentence carries, in millionths of a degree as the GPS sketch rounds them
// (ddmm.mmmmm: minutes / 60), from the bytes the firmware received on the GPS's port.
std::vector<std::pair<long, long>> gga_fixes(const std::string& received) {
  std::vector<std::pair<long, long>> fixes;
  const std::regex gga(R"(\$GPGGA,[0-9.]*,(\d\d)(\d\d\.\d+),([NS]),(\d\d\d)(\d\d\.\d+),([EW]),[1-8],)");
  for (std::sregex_iterator m(received.begin(), received.end(), gga), end; m != end; ++m) {
    const auto e6 = [&](int deg, int min) {
      return std::lround((std::stod((*m)[deg]) + std::stod((*m)[min]) / 60.0) * 1e6);
    };
    fixes.emplace_back(e6(1, 2) * ((*m)[3] == "S" ? -1 : 1), e6(4, 5) * ((*m)[6] == "W" ? -1 : 1));
  }
  return fixes;
}

// The GPS sketch parses what the NEO-6M sends on Serial1: each fix it prints is the $GPGGA's to the
// millionth of a degree, on the host layer and built with the genuine core for the AVR engine
// (where a long is 32 bits: the sketch's arithmetic stays within it) alike. The receiver's first
// fix comes at its 2 s ttff, then one a second: four by 6 s. Each within 4 CEP (10 m) of the
// origin the rover stands on, which a fix misses with odds of 2^-16 (Rayleigh: 2^-(r/CEP)^2).
TEST(GpsSketch, PrintsTheFixesTheReceiverSentOnBothEngines) {
  std::vector<std::string> printed[2];
  for (const bool chip : {false, true}) {
    TempDir dir;
    const SearRun run = run_project(dir, std::string(SEAR_EXAMPLES_DIR) + "/arduino/gps_sketch/project.xml",
                                    chip ? "--engine avr" : "");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    if (chip) {  // the chip's build ran on the AVR engine, not the host build in its place
      ASSERT_TRUE(nlohmann::json::parse(run.file("summary.json"))["avr_engines"]["rover.main"].is_object());
    }
    const auto sent = gga_fixes(run.file("rover.main.uart1.rx.bin"));
    std::vector<std::pair<long, long>> got;
    for (const auto& line : lines_of(run.file("rover.main.console.log"))) {
      printed[chip].push_back(line.substr(line.find(' ') + 1));
      double lat = 0, lon = 0;
      if (std::sscanf(line.c_str(), "%*s fix %lf %lf", &lat, &lon) != 2) continue;
      got.emplace_back(std::lround(lat * 1e6), std::lround(lon * 1e6));
      const double north_m = (lat - 52.2053) * 111320.0, east_m = (lon - 0.1218) * 111320.0 * std::cos(52.2053 * M_PI / 180);
      EXPECT_LT(std::hypot(north_m, east_m), 4 * 2.5) << line;
    }
    EXPECT_EQ(got.size(), 4u) << run.file("rover.main.console.log");
    EXPECT_EQ(got, sent);
  }
  EXPECT_EQ(printed[0], printed[1]);
}

// As on the Mega, the first Servo takes Timer5: PWM on pin 45 afterwards stops the MCU, and the
// run's summary names the call; what the sketch printed before it still went out.
TEST(RefusedSketch, AnalogWriteOnTimer5AfterAServoStopsTheMcuWithTheCallNamed) {
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project("    <mcu name=\"main\">\n      <firmware sketch=\"" +
                                                  std::string(REFUSED_PWM_SKETCH) + "\"/>\n    </mcu>\n",
                                                  "", 0.2));
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.out.find("analogWrite() on pin 44, 45 or 46: the first Servo took Timer5"), std::string::npos)
      << run.out;
  EXPECT_EQ(run.out.find("not reached"), std::string::npos);
}

// `sear` with `args`, output in dir/stdout and dir/stderr.
int run_command(const TempDir& dir, const std::string& args) {
  const std::string cmd = std::string(SEAR_BINARY) + " " + args + " >" + (dir.path() / "stdout").string() + " 2>" +
                          (dir.path() / "stderr").string();
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// `sear new --arduino` writes DIR/DIR.ino and a project that runs as it stands: its expectations
// (the sonar's first reading 1.30 m from the wall, turning away before touching it) pass.
TEST(ArduinoTemplate, WritesASketchProjectWhoseExpectationsPass) {
  TempDir dir;
  const auto project = dir.path() / "Roamer";
  ASSERT_EQ(run_command(dir, "new " + project.string() + " --arduino"), 0) << read_file(dir.path() / "stderr");
  EXPECT_TRUE(std::filesystem::is_regular_file(project / "Roamer.ino"));
  EXPECT_TRUE(std::filesystem::is_regular_file(project / "robot.xml"));
  EXPECT_FALSE(std::filesystem::exists(project / "CMakeLists.txt"));  // the C template's build
  EXPECT_FALSE(std::filesystem::exists(project / "sketch.ino"));
  EXPECT_TRUE(std::filesystem::is_regular_file(project / ".gitignore"));
  const int code = run_command(dir, "run " + project.string() + " -o " + (dir.path() / "out").string());
  EXPECT_EQ(code, 0) << read_file(dir.path() / "stdout") << read_file(dir.path() / "stderr");
  const std::string summary = read_file(dir.path() / "out" / "summary.json");
  EXPECT_NE(summary.find("\"passed\""), std::string::npos) << summary;
}

// A sketch folder with no project.xml runs on the default Arduino robot: its HC-SR04 (TRIG 24,
// ECHO 2, 0.15 m ahead) sees the wall whose face is 1.45 m ahead of the rover's centre, 130 cm
// (7540 us at 58 us/cm) within the model's 3 mm noise and the truncation to whole cm.
TEST(SketchWithoutProject, RunsOnTheDefaultArduinoRobot) {
  TempDir dir;
  const auto sketch = dir.path() / "Ranger";
  std::filesystem::create_directories(sketch);
  std::ofstream(sketch / "Ranger.ino") << "void setup() { Serial.begin(9600); pinMode(24, OUTPUT); }\n"
                                          "void loop() {\n  digitalWrite(24, HIGH); delayMicroseconds(10); "
                                          "digitalWrite(24, LOW);\n  Serial.println(pulseIn(2, HIGH) / 58);\n"
                                          "  delay(60);\n}\n";
  for (const std::string& argument : {sketch.string() + "/", (sketch / "Ranger.ino").string()}) {
    SCOPED_TRACE(argument);
    const auto out = dir.path() / "out";
    std::filesystem::remove_all(out);
    ASSERT_EQ(run_command(dir, "run " + argument + " -d 0.5 -o " + out.string()), 0)
        << read_file(dir.path() / "stdout") << read_file(dir.path() / "stderr");
    int readings = 0;
    for (const auto& line : lines_of(read_file(out / "rover.main.console.log"))) {
      long cm = 0;
      if (std::sscanf(line.c_str(), "%*s %ld", &cm) != 1) continue;
      ++readings;
      EXPECT_NEAR(static_cast<double>(cm), 129.5, 1.0) << line;
    }
    EXPECT_GE(readings, 5);  // one per ~68 ms over 0.5 s
  }
}

// SoftwareSerial on the Mega receives only on the pin-change pins (10..15, 50..53, A8..A15): on
// pin 2 begin() stops the MCU with the call and the pins to use; what it printed before went out.
TEST(SoftwareSerialSketch, BeginOnAPinWithoutPinChangeStopsTheMcuNamingTheCall) {
  TempDir dir;
  const auto sketch = dir.path() / "soft_gps";
  std::filesystem::create_directories(sketch);
  std::ofstream(sketch / "soft_gps.ino") << "#include <SoftwareSerial.h>\nSoftwareSerial gps(2, 3);\n"
                                            "void setup() { Serial.begin(9600); Serial.println(\"before\"); "
                                            "gps.begin(9600); }\nvoid loop() {}\n";
  const SearRun run = run_sear(dir, rover_project("    <mcu name=\"main\">\n      <firmware sketch=\"" +
                                                  sketch.string() + "/\"/>\n    </mcu>\n",
                                                  "", 0.1));
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.out.find("SoftwareSerial(2, 3).begin(9600): RX pin 2 has no pin-change interrupt"), std::string::npos)
      << run.out << run.err;
  EXPECT_NE(run.out.find("the Mega receives on 10..15, 50..53, A8..A15"), std::string::npos);
  EXPECT_NE(run.file("rover.main.console.log").find("before"), std::string::npos);
}

// A sketch folder `name` holding name.ino with `code`, run for `duration_s` with `devices` in its
// <mcu>; the console (Serial) at 115200 baud so that forwarding 9600 baud never falls behind.
SearRun run_sketch(const TempDir& dir, const std::string& name, const std::string& code, const std::string& devices,
                   double duration_s) {
  const auto sketch = dir.path() / name;
  std::filesystem::create_directories(sketch);
  std::ofstream(sketch / (name + ".ino")) << code;
  return run_sear(dir, rover_project("    <mcu name=\"main\">\n      <firmware sketch=\"" + sketch.string() +
                                         "/\"/>\n" + devices + "    </mcu>\n",
                                     "", duration_s));
}

const char* const kForwardSoft =
    "#include <SoftwareSerial.h>\nSoftwareSerial gps(10, 11);\n"
    "void setup() { Serial.begin(115200); gps.begin(9600); }\n"
    "void loop() { while (gps.available()) Serial.write(gps.read()); }\n";

// An MTK3339 at 9600 baud on the soft UART's pins (its TX drives pin 10 edge by edge) gives the
// sketch exactly the bytes it gives a hardware port: the same project and seed with the GPS on
// Serial1 is the reference, whose port captured every byte the model sent. The soft run forwards
// each byte after its stop bit's middle, so at the run's end at most its last two bytes (one in
// its frame, one on the console's line) are still to come; all before are equal, byte for byte.
TEST(SoftwareSerialSketch, ReceivesTheGpsSentencesByteForByteAsAHardwarePortDoes) {
  TempDir soft_dir, soft_again_dir, port_dir;
  const SearRun soft = run_sketch(soft_dir, "soft_gps", kForwardSoft,
                                  "      <mtk3339 name=\"gps\" uart=\"soft:10,11\" pos=\"0 0 0.1\"/>\n", 1.3);
  ASSERT_EQ(soft.exit_code, 0) << soft.out << soft.err;
  const SearRun port = run_sketch(port_dir, "port_gps",
                                  "void setup() { Serial.begin(115200); Serial1.begin(9600); }\n"
                                  "void loop() { while (Serial1.available()) Serial.write(Serial1.read()); }\n",
                                  "      <mtk3339 name=\"gps\" uart=\"1\" pos=\"0 0 0.1\"/>\n", 1.3);
  ASSERT_EQ(port.exit_code, 0) << port.out << port.err;
  const std::string sent = port.file("rover.main.uart1.rx.bin");
  const std::string got = soft.file("rover.main.uart0.tx.bin");
  ASSERT_GT(sent.size(), 150u) << sent;  // the boot messages and a second of NMEA sentences
  EXPECT_NE(sent.find("$GPGGA"), std::string::npos) << sent;
  ASSERT_GE(got.size() + 2, sent.size());
  EXPECT_EQ(got, sent.substr(0, got.size()));
  // Same project, same seed: the same bytes.
  const SearRun again = run_sketch(soft_again_dir, "soft_gps", kForwardSoft,
                                   "      <mtk3339 name=\"gps\" uart=\"soft:10,11\" pos=\"0 0 0.1\"/>\n", 1.3);
  ASSERT_EQ(again.exit_code, 0);
  EXPECT_EQ(again.file("rover.main.uart0.tx.bin"), got);
}

#ifdef SOFT_GPS_AVR
// The genuine SoftwareSerial of Debian's arduino-core-avr on the AVR engine, receiving from
// pin-change interrupts on pin 10 as on the chip, gets the same bytes from the GPS's pin edges as
// a hardware port of the native build does (same project and seed): the pin-level device serves
// both engines. The forwarding lags by the same at most two bytes as above.
TEST(SoftwareSerialSketch, TheGenuineLibraryOnTheAvrEngineReceivesTheSameGpsBytes) {
  TempDir avr_dir, port_dir;
  const SearRun avr = run_sear(
      avr_dir, rover_project("    <mcu name=\"main\" engine=\"avr\">\n      <firmware elf=\"" + std::string(SOFT_GPS_AVR) +
                                 "\"/>\n      <mtk3339 name=\"gps\" uart=\"soft:10,11\" pos=\"0 0 0.1\"/>\n    </mcu>\n",
                             "", 1.3));
  ASSERT_EQ(avr.exit_code, 0) << avr.out << avr.err;
  const SearRun port = run_sketch(port_dir, "port_gps",
                                  "void setup() { Serial.begin(115200); Serial1.begin(9600); }\n"
                                  "void loop() { while (Serial1.available()) Serial.write(Serial1.read()); }\n",
                                  "      <mtk3339 name=\"gps\" uart=\"1\" pos=\"0 0 0.1\"/>\n", 1.3);
  ASSERT_EQ(port.exit_code, 0) << port.out << port.err;
  const std::string sent = port.file("rover.main.uart1.rx.bin");
  const std::string got = avr.file("rover.main.uart0.tx.bin");
  ASSERT_GT(sent.size(), 150u);
  ASSERT_GE(got.size() + 2, sent.size());
  EXPECT_EQ(got, sent.substr(0, got.size()));
}
#endif

// What the sketch sends on the soft TX pin reaches the GPS decoded from the pin's edges: a PMTK220
// command (fix interval 200 ms) is acknowledged with $PMTK001,220,3 (3: valid and done, MTK NMEA
// packet manual, packet 001), which comes back on the soft RX pin.
TEST(SoftwareSerialSketch, ACommandSentOnTheSoftTxPinIsAcknowledgedByTheGps) {
  TempDir dir;
  const SearRun run = run_sketch(dir, "soft_cmd",
                                 "#include <SoftwareSerial.h>\nSoftwareSerial gps(10, 11);\n"
                                 "void setup() { Serial.begin(115200); gps.begin(9600); delay(300);\n"
                                 "  gps.print(\"$PMTK220,200*2C\\r\\n\"); }\n"
                                 "void loop() { while (gps.available()) Serial.write(gps.read()); }\n",
                                 "      <mtk3339 name=\"gps\" uart=\"soft:10,11\" pos=\"0 0 0.1\"/>\n", 0.6);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.file("rover.main.uart0.tx.bin").find("$PMTK001,220,3*"), std::string::npos)
      << run.file("rover.main.uart0.tx.bin");
}

// The library's one shared 64-byte ring keeps one slot empty: 1.5 s of the GPS (its boot messages
// and first sentences, over 150 bytes) unread leaves 63 waiting and overflow() true, once (it
// clears as it is asked). A second object's begin() makes it the listener: the first then has
// nothing available and is no longer listening.
TEST(SoftwareSerialSketch, TheRingHolds63BytesAndOneObjectListensAtATime) {
  TempDir dir;
  const SearRun run = run_sketch(dir, "soft_ring",
                                 "#include <SoftwareSerial.h>\nSoftwareSerial gps(10, 11);\nSoftwareSerial other(12, 13);\n"
                                 "void setup() { Serial.begin(115200); gps.begin(9600); delay(1500);\n"
                                 "  Serial.print(gps.available()); Serial.print(' '); Serial.print(gps.overflow());\n"
                                 "  Serial.print(' '); Serial.println(gps.overflow());\n"
                                 "  other.begin(9600);\n"
                                 "  Serial.print(gps.isListening()); Serial.print(' '); Serial.print(other.isListening());\n"
                                 "  Serial.print(' '); Serial.println(gps.available()); }\n"
                                 "void loop() {}\n",
                                 "      <mtk3339 name=\"gps\" uart=\"soft:10,11\" pos=\"0 0 0.1\"/>\n", 1.6);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const std::string console = run.file("rover.main.console.log");
  EXPECT_NE(console.find(" 63 1 0\n"), std::string::npos) << console;
  EXPECT_NE(console.find(" 0 1 0\n"), std::string::npos) << console;
}

// A soft wire the sketch could not use is refused at load, naming the file's line and the
// attribute: an RX pin SoftwareSerial cannot receive on (no pin-change interrupt; the message
// names the pins that work), and a wire without both pins, RX then TX, as SoftwareSerial(RX, TX)
// takes them.
struct BadSoftWire {
  const char* uart;
  const char* says;
};

class SoftwareSerialWiring : public ::testing::TestWithParam<BadSoftWire> {};

TEST_P(SoftwareSerialWiring, IsRefusedWithTheLineAndWhy) {
  TempDir dir;
  const SearRun run = run_sketch(dir, "soft_bad", kForwardSoft,
                                 std::string("      <mtk3339 name=\"gps\" uart=\"") + GetParam().uart +
                                     "\" pos=\"0 0 0.1\"/>\n",
                                 0.1);
  EXPECT_NE(run.exit_code, 0);
  const std::string all = run.out + run.err;
  EXPECT_NE(all.find("project.xml:10: error"), std::string::npos) << all;  // the <mtk3339>'s line
  EXPECT_NE(all.find(GetParam().says), std::string::npos) << all;
}

INSTANTIATE_TEST_SUITE_P(
    Wires, SoftwareSerialWiring,
    ::testing::Values(BadSoftWire{"soft:2,11", "<mtk3339> 'uart' \"soft:2,11\": RX pin 2 has no pin-change interrupt"},
                      BadSoftWire{"soft:10", "<mtk3339> 'uart' \"soft:10\" must be soft:RX,TX"}),
    case_name<BadSoftWire>);

// `while (true);` at the end of loop(), the Arduino idiom for "stop here": the MCU halts there and
// the run goes on to its end and exits 0. The line printed before it still leaves byte by byte at
// 9600 baud, and the tone started in setup() (Timer2's compare interrupt) still toggles its pin
// every 500 us to the end.
TEST(HaltingSketch, WhileTrueAtTheEndOfLoopHaltsTheMcuAndItsInterruptsRunOn) {
  TempDir dir;
  const auto sketch = dir.path() / "halting";
  std::filesystem::create_directories(sketch);
  const std::string line = "loop ran once, then halted";
  std::ofstream(sketch / "halting.ino") << "void setup() { Serial.begin(9600); tone(8, 1000); }\n"
                                           "void loop() {\n  Serial.println(\"" << line << "\");\n  while (true);\n}\n";
  const double duration_s = 0.3;
  const SearRun run = run_sear(dir, rover_project("    <mcu name=\"main\">\n      <firmware sketch=\"" +
                                                  sketch.string() + "/\"/>\n    </mcu>\n",
                                                  "", duration_s));
  ASSERT_EQ(run.exit_code, 0) << run.err << run.out;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  ASSERT_EQ(summary["mcu_halts"].size(), 1u) << summary.dump();
  EXPECT_EQ(summary["mcu_halts"][0]["interrupts"], "on");
  const auto halted_ns = std::llround(summary["mcu_halts"][0]["sim_time_s"].get<double>() * 1e9);
  EXPECT_NE(run.out.find("mcu rover.main halted at sim time"), std::string::npos) << run.out;

  // The line and its CR LF, once (loop() never came round again), each byte 10 bit times after
  // the one before; the loop began once println() had queued them all, before the first left.
  const auto console = lines_of(run.file("rover.main.console.log"));
  ASSERT_EQ(console.size(), 1u) << run.file("rover.main.console.log");
  EXPECT_EQ(console[0].substr(console[0].find(' ') + 1), line);
  std::vector<std::int64_t> sent;
  for (const auto& l : lines_of(run.file("rover.main.uart0.log"))) {
    long long s = 0, ns = 0;
    char direction[4] = {};
    if (std::sscanf(l.c_str(), "%lld.%9lld %3s", &s, &ns, direction) == 3 && std::string(direction) == "tx")
      sent.push_back(s * 1000000000 + ns);
  }
  ASSERT_EQ(sent.size(), line.size() + 2);
  EXPECT_LT(halted_ns, sent.front());
  EXPECT_NEAR(static_cast<double>(sent.back() - sent.front()), static_cast<double>(line.size() + 1) * 1e10 / 9600, 1.0);
  // Timer2 toggles pin 8 every 500 us (prescaler 32, OCR2A 249) up to the run's end.
  const auto changes = vcd_changes(run.file("rover.main.pins.vcd"), vcd_id_of_pin(8));
  ASSERT_GE(changes.size(), 3u);
  std::size_t after_halt = 0;
  for (std::size_t k = 3; k < changes.size(); ++k) {
    EXPECT_EQ(changes[k].time - changes[k - 1].time, 500000) << "edge " << k;
    if (changes[k].time > halted_ns) ++after_halt;
  }
  // 0.3 s of 500 us half-periods: 599 or 600 edges after the first few microseconds.
  EXPECT_GE(after_halt, 598u);
  EXPECT_GT(changes.back().time, std::llround((duration_s - 0.0005) * 1e9));
}

// Splits one pin's VCD changes into bursts: a gap longer than `gap_ns` starts a new one.
std::vector<std::vector<VcdChange>> bursts(const std::vector<VcdChange>& changes, std::int64_t gap_ns) {
  std::vector<std::vector<VcdChange>> out;
  for (const auto& c : changes) {
    if (out.empty() || c.time - out.back().back().time > gap_ns) out.emplace_back();
    out.back().push_back(c);
  }
  return out;
}

// Timer2 in CTC mode toggles the pin at each compare match (ATmega2560 datasheet 20.7.2):
// f = f_clk / (2 * N * (1 + OCR2A)), N the prescaler the core picks (Tone.cpp: the smallest of
// 1, 8, 32, 64, 128, 256, 1024 whose OCR2A fits 8 bits). Each half-period here is a whole number
// of microseconds, so the edges fall on the exact nanosecond.
std::int64_t half_period_ns(unsigned frequency) {
  const unsigned prescalers[] = {1, 8, 32, 64, 128, 256, 1024};
  unsigned long ocr = 0, n = 1;
  for (unsigned p : prescalers) {
    n = p;
    ocr = 16000000UL / frequency / 2 / p - 1;
    if (ocr <= 255) break;
  }
  return static_cast<std::int64_t>(((ocr & 0xFF) + 1) * n) * 1000 / 16;  // 62.5 ns a cycle
}

TEST(ToneSketch, SquareWavesAtTimer2sFrequencyForTheirDuration) {
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project("    <mcu name=\"main\">\n      <firmware sketch=\"" +
                                                  std::string(TONE_SKETCH) + "\"/>\n    </mcu>\n",
                                                  "", 0.6));
  ASSERT_EQ(run.exit_code, 0) << run.err << run.out;
  EXPECT_NE(run.file("rover.main.console.log").find("done"), std::string::npos);
  const std::string vcd = run.file("rover.main.pins.vcd");
  auto changes = vcd_changes(vcd, vcd_id_of_pin(8));
  ASSERT_GE(changes.size(), 2u) << vcd.substr(0, 2000);
  EXPECT_EQ(changes[0].value, 'z');  // an input until tone()'s pinMode
  EXPECT_EQ(changes[1].value, '0');
  changes.erase(changes.begin(), changes.begin() + 2);
  const auto notes = bursts(changes, 10000000);  // the sketch waits 50 ms or more between notes
  ASSERT_EQ(notes.size(), 3u) << vcd;

  // tone(8, 440, 100): prescaler 128, OCR2A 141, 1136 us a half-period (440.14 Hz); the core
  // counts 2 * 440 * 100 / 1000 = 88 toggles, so the pin ends LOW after 99.968 ms.
  EXPECT_EQ(half_period_ns(440), 1136000);
  ASSERT_EQ(notes[0].size(), 88u);
  for (std::size_t k = 1; k < notes[0].size(); ++k) {
    EXPECT_EQ(notes[0][k].time - notes[0][k - 1].time, half_period_ns(440)) << "edge " << k;
    EXPECT_EQ(notes[0][k].value, k % 2 == 0 ? '1' : '0');
  }
  // tone(8, 1000) until noTone() 20 ms later: prescaler 32, OCR2A 249, 500 us; 40 half-periods
  // fit in the 20 ms, the last one at the moment noTone() comes or just before it.
  EXPECT_EQ(half_period_ns(1000), 500000);
  EXPECT_GE(notes[1].size(), 39u);
  EXPECT_LE(notes[1].size(), 41u);
  for (std::size_t k = 1; k < notes[1].size(); ++k)
    EXPECT_EQ(notes[1][k].time - notes[1][k - 1].time, half_period_ns(1000)) << "edge " << k;
  EXPECT_EQ(notes[1].back().value, '0');  // noTone() leaves the pin LOW
  // tone(8, 30, 100): /1024 gives OCR2A 259, which the 8-bit register keeps as 3: 256 us
  // half-periods (1953 Hz), as the chip plays it; 2 * 30 * 100 / 1000 = 6 toggles.
  EXPECT_EQ(half_period_ns(30), 256000);
  ASSERT_EQ(notes[2].size(), 6u);
  for (std::size_t k = 1; k < notes[2].size(); ++k)
    EXPECT_EQ(notes[2][k].time - notes[2][k - 1].time, half_period_ns(30));

  // Timer2's set-up disconnects OC2B: the PWM on pin 9 (duty 128) ends when the first tone starts;
  // after noTone() the timer is free and analogWrite(10, 64) runs.
  const std::string values = run.file("rover.main.values.vcd");
  const auto duty = [&](const std::string& name) {
    std::smatch m;
    std::vector<std::string> seen;
    if (!std::regex_search(values, m, std::regex("\\$var reg 8 (\\S+) " + name + " \\$end"))) return seen;
    for (const auto& line : lines_of(values))
      if (line.size() > 2 && line[0] == 'b' && line.substr(line.find(' ') + 1) == m[1].str())
        seen.push_back(line.substr(1, line.find(' ') - 1));
    return seen;
  };
  // "z" is $dumpvars: no PWM yet.
  EXPECT_EQ(duty("D9_pwm"), (std::vector<std::string>{"z", "10000000", "0"})) << values.substr(0, 3000);
  EXPECT_EQ(duty("D10_pwm"), (std::vector<std::string>{"z", "1000000"}));

  // The core has one tone pin: tone(11, 2000) while pin 8 plays does nothing, not even pinMode.
  const auto pin11 = vcd_changes(vcd, vcd_id_of_pin(11));
  ASSERT_EQ(pin11.size(), 1u);
  EXPECT_EQ(pin11[0].value, 'z');
}

// analogWrite on Timer2's pins while a tone holds the timer would change its pitch on the chip:
// the MCU stops with the call named.
TEST(ToneSketch, AnalogWriteOnTimer2WhileATonePlaysStopsTheMcuWithTheCallNamed) {
  TempDir dir;
  const auto sketch = dir.path() / "tone_pwm";
  std::filesystem::create_directories(sketch);
  std::ofstream(sketch / "tone_pwm.ino") << "void setup() { tone(8, 440); analogWrite(10, 50); }\nvoid loop() {}\n";
  const SearRun run = run_sear(dir, rover_project("    <mcu name=\"main\">\n      <firmware sketch=\"" +
                                                  sketch.string() + "/\"/>\n    </mcu>\n",
                                                  "", 0.1));
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.out.find("analogWrite() on pin 9 or 10 while tone() plays"), std::string::npos) << run.out;
}

}  // namespace
