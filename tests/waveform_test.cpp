// The per-MCU VCD waveforms read back by independent readers: GTKWave's vcd2fst converts them to
// FST and fst2vcd writes them out again, and what the firmware did (tests/firmware/waveform_probe.c)
// is checked in that round-tripped text: pin levels, PWM duties, servo pulses and UART bytes at
// the times the firmware's delays and the baud rates put them; sigrok's UART decoder reads the
// USART pins' frames.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "exporters/edge_streams.hpp"
#include "exporters/pin_waveform.hpp"
#include "command_output.hpp"
#include "firmware_run.hpp"

extern "C" {
#include "board.h"
}

namespace sear::test {
namespace {

namespace fs = std::filesystem;

constexpr std::int64_t kMs = 1000000;  // ns
constexpr int kZ = -1;                 // 'z' or 'x': nothing driven, no byte

struct Change {
  std::int64_t t;
  int value;
  bool operator==(const Change& o) const { return t == o.t && value == o.value; }
};
std::ostream& operator<<(std::ostream& out, const Change& c) { return out << "(" << c.t << ", " << c.value << ")"; }

using Waves = std::map<std::string, std::vector<Change>>;

int value_of(const std::string& bits) {
  int v = 0;
  for (char c : bits) {
    if (c != '0' && c != '1') return kZ;
    v = v * 2 + (c - '0');
  }
  return v;
}

// Every variable's changes by name, as a viewer shows them: of several changes at one time only
// the last, and none to the value already shown, so two equal bytes in a row count only if
// something else showed between them.
Waves read_vcd(const std::string& text) {
  std::map<std::string, std::string> name_of;  // by identifier
  Waves waves;
  std::int64_t t = 0;
  bool body = false;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string first;
    if (!(words >> first)) continue;
    if (first == "$var") {
      std::string type, size, id, name;
      words >> type >> size >> id >> name;
      name_of[id] = name;
    } else if (first == "$enddefinitions") {
      body = true;
    } else if (body && first[0] == '#') {
      t = std::stoll(first.substr(1));
    } else if (body && first[0] != '$') {
      std::string id;
      int value;
      if (first[0] == 'b') {
        words >> id;
        value = value_of(first.substr(1));
      } else {
        id = first.substr(1);
        value = value_of(first.substr(0, 1));
      }
      auto& changes = waves[name_of.at(id)];
      if (!changes.empty() && changes.back().t == t) changes.pop_back();  // the last at one time is what shows
      if (changes.empty() || changes.back().value != value) changes.push_back({t, value});
    }
  }
  return waves;
}

// vcd2fst, then fst2vcd: what GTKWave itself would load from the file.
std::string round_trip(const fs::path& vcd, const fs::path& work) {
  const fs::path fst = work / "waves.fst", back = work / "back.vcd", err = work / "reader.err";
  const std::string cmd = "vcd2fst " + vcd.string() + " " + fst.string() + " >" + err.string() + " 2>&1 && fst2vcd " +
                          fst.string() + " >" + back.string() + " 2>>" + err.string();
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd << "\n" << read_file(err);
  EXPECT_EQ(read_file(err), "");  // the reader found nothing to warn about
  return read_file(back);
}

// Stop bit end of byte n (from 1) of a burst from `start`: n frames of 10 bits (8N1) at the baud,
// rounded to the VCD's nanosecond.
std::int64_t stop_end(std::int64_t start, int n, double baud) { return start + std::llround(n * 10 * 1e9 / baud); }
std::int64_t nine_bits(double baud) { return std::llround(9 * 1e9 / baud); }

TEST(Waveform, TheFirmwaresDutiesPulsesAndBytesReadBackThroughGtkwave) {
  TempDir dir;
  // Every HAL call takes no time (hal_call_cycles 0), so each moment is a delay's end.
  const std::string mcu = std::string("    <mcu name=\"main\" hal_call_cycles=\"0\">\n      <firmware executable=\"") +
                          WAVEFORM_PROBE + "\"/>\n      <uart port=\"1\" loopback=\"true\"/>\n    </mcu>\n";
  // --uart-frames: the values show the UART bytes only with it.
  const SearRun run = run_sear(dir, rover_project(mcu, "", 0.1), "--quiet --uart-frames");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  TempDir again_dir;
  const SearRun again = run_sear(again_dir, read_file(dir.path() / "project.xml"), "--quiet --uart-frames");
  for (const char* file : {"rover.main.pins.vcd", "rover.main.values.vcd"}) {
    EXPECT_EQ(again.file(file), run.file(file));  // deterministic
    // The reader kept every change the file holds.
    EXPECT_EQ(read_vcd(round_trip(run.dir / file, dir.path())), read_vcd(run.file(file))) << file;
  }
  Waves waves = read_vcd(run.file("rover.main.pins.vcd"));
  waves.merge(read_vcd(run.file("rover.main.values.vcd")));

  // pwm_write(3, ...) every 10 ms from 5 ms; 0 and a digital write are plain levels (duties 0 and
  // 255); an input drives nothing.
  EXPECT_EQ(waves.at("D3_pwm"), (std::vector<Change>{{0, kZ},
                                                      {5 * kMs, 64},
                                                      {15 * kMs, 200},
                                                      {25 * kMs, 0},
                                                      {35 * kMs, 128},
                                                      {45 * kMs, 255},
                                                      {55 * kMs, kZ}}));
  EXPECT_EQ(waves.at("D3"), (std::vector<Change>{{0, kZ}, {5 * kMs, 0}, {45 * kMs, 1}, {55 * kMs, kZ}}));
  EXPECT_EQ(waves.at("D44_servo_us"), (std::vector<Change>{{0, kZ}, {5 * kMs, 1500}, {25 * kMs, 2000}, {45 * kMs, 0}}));
  EXPECT_EQ(waves.at("D44"), (std::vector<Change>{{0, kZ}, {5 * kMs, 0}}));  // the servo pin's level is not the pulses
  EXPECT_EQ(waves.at("D13_pwm"), (std::vector<Change>{{0, kZ}}));           // never written

  // Bytes on a line as a receiver's data register would hold them: each from its stop bit's
  // end, for nine bit times and then 'z' unless the next byte, back to back, differs.
  auto bytes = [](const std::string& sent, std::int64_t start, double baud) {
    std::vector<Change> shown{{0, kZ}};
    for (std::size_t n = 1; n <= sent.size(); ++n) {
      shown.push_back({stop_end(start, static_cast<int>(n), baud), static_cast<std::uint8_t>(sent[n - 1])});
      if (n == sent.size() || sent[n] == sent[n - 1])
        shown.push_back({stop_end(start, static_cast<int>(n), baud) + nine_bits(baud), kZ});
    }
    return shown;
  };
  // "AAB" at 9600 baud from 0 s: the two A's apart, A and B joined; the looped-back RX carries
  // the same bytes at the same times.
  EXPECT_EQ(waves.at("uart1_tx_loopback"), bytes("AAB", 0, 9600));
  EXPECT_EQ(waves.at("uart1_rx_loopback"), bytes("AAB", 0, 9600));
  EXPECT_EQ(waves.at("uart1_tx_loopback").size(), 6u);  // 'z' at 0, A, 'z', A, B, 'z'
  // 64 bytes back to back at 500 kbaud from 60 ms, each value twice: 20 us a frame.
  std::string burst;
  for (int i = 0; i < 64; ++i) burst += static_cast<char>(i / 2);
  EXPECT_EQ(waves.at("uart2_tx"), bytes(burst, 60 * kMs, 500000));
  for (const char* quiet : {"uart0_tx_console.rx", "uart0_rx_console.tx", "uart2_rx", "uart3_tx", "uart3_rx"})
    EXPECT_EQ(waves.at(quiet), (std::vector<Change>{{0, kZ}})) << quiet;
}

// A byte's frame on its USART pin, as a logic analyser sees it: the line idles high; bit k (0 the
// start bit, low; 1..8 the data from the least significant; 9 the stop bit, high) of byte n of a
// burst from `start` begins at start + (10 n + k) bit times, rounded to the nanosecond.
std::vector<Change> frames(const std::string& sent, std::int64_t start, double baud) {
  std::vector<Change> edges;
  int shown = 1;
  for (std::size_t n = 0; n < sent.size(); ++n)
    for (int k = 0; k < 10; ++k) {
      const int level = k == 0 ? 0 : k == 9 ? 1 : (static_cast<std::uint8_t>(sent[n]) >> (k - 1)) & 1;
      if (level == shown) continue;
      shown = level;
      edges.push_back({std::llround(static_cast<double>(start) + (10.0 * static_cast<double>(n) + k) * 1e9 / baud), level});
    }
  return edges;
}

// Each edge within 1 ns of where it is due: the capture places a bit's edge back from the byte's
// stop-bit end as the HAL rounds that end, each rounding to the nanosecond.
void expect_edges(const std::vector<Change>& got, const std::vector<Change>& want, const char* pin) {
  ASSERT_EQ(got.size(), want.size()) << pin;
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_NEAR(static_cast<double>(got[i].t), static_cast<double>(want[i].t), 1.0) << pin << " edge " << i;
    EXPECT_EQ(got[i].value, want[i].value) << pin << " edge " << i;
  }
}

// sigrok's UART decoder (sigrok-cli) reading one pin of the VCD as a logic analyser's capture,
// sampled at 10 MHz (20 samples a bit at 500 kbaud): the bytes it decodes, as hex.
std::string sigrok_uart(const fs::path& vcd, const std::string& pin, int baud) {
  const auto run = command_output("sigrok-cli -I vcd:downsample=100 -i " + vcd.string() + " -P uart:rx=" + pin +
                                  ":baudrate=" + std::to_string(baud) + " -A uart=rx-data 2>&1");
  std::string bytes;
  for (const auto& line : lines_of(run.out)) bytes += line.substr(line.find(": ") + 2) + " ";
  return bytes;
}

std::string hex_of(const std::string& bytes) {
  std::string out;
  char b[4];
  for (const char c : bytes) {
    std::snprintf(b, sizeof b, "%02X ", static_cast<std::uint8_t>(c));
    out += b;
  }
  return out;
}

std::string waveform_probe_mcu(const char* cycles) {
  return std::string("    <mcu name=\"main\" hal_call_cycles=\"") + cycles + "\">\n      <firmware executable=\"" +
         WAVEFORM_PROBE + "\"/>\n      <uart port=\"1\" loopback=\"true\"/>\n    </mcu>\n";
}

// With --uart-frames the pins a logic analyser would probe carry the frames of every byte: TX1
// (D18) and the looped-back RX1 (D19) "AAB" at 9600 baud from 0 s, TX2 (D16) the 500 kbaud burst
// from 60 ms, each edge where the frame puts it, and sigrok's UART decoder reads the same bytes
// off them.
TEST(Waveform, UartPinsCarryTheirFramesForALogicAnalysersDecoder) {
  TempDir dir;
  const SearRun run = run_sear(dir, rover_project(waveform_probe_mcu("0"), "", 0.1), "--quiet --uart-frames");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Waves waves = read_vcd(run.file("rover.main.pins.vcd"));
  std::vector<Change> tx1{{0, 1}};  // uart_begin at 0: the line idles high
  for (const Change& c : frames("AAB", 0, 9600)) tx1.push_back(c);
  // The first edge falls at 0 too, where the idle level was shown: what a viewer shows is the last.
  tx1.erase(tx1.begin());
  expect_edges(waves.at("D18_loopback"), tx1, "D18");
  expect_edges(waves.at("D19_loopback"), tx1, "D19");
  std::string burst;
  for (int i = 0; i < 64; ++i) burst += static_cast<char>(i / 2);
  std::vector<Change> tx2{{0, kZ}};  // its uart_begin's idle level at 60 ms gives way to the first start bit
  for (const Change& c : frames(burst, 60 * kMs, 500000)) tx2.push_back(c);
  expect_edges(waves.at("D16"), tx2, "D16");
  EXPECT_EQ(waves.at("D1_console.rx"), (std::vector<Change>{{0, kZ}}));  // UART 0 never began
  // Written after D4's change at 1.5 ms, the second byte's frame still has its own edges, from
  // 1.04 ms on: the waveform stays a frame behind the run.
  EXPECT_EQ(waves.at("D4"), (std::vector<Change>{{0, 0}, {1500000, 1}}));

  if (std::system("command -v sigrok-cli >/dev/null") != 0) {
    if (std::getenv("CI")) FAIL() << "sigrok-cli is missing (scripts/install-deps.sh installs it)";
    GTEST_SKIP() << "sigrok-cli is not installed";
  }
  // A decoder finds a frame by its start bit's falling edge, so it needs the line idle before the
  // first; with calls that take no time a port's first byte starts the instant it began. With the
  // default cost the line idles high for one call, 3.125 us (31 samples at 10 MHz), first.
  TempDir costed_dir;
  const SearRun costed = run_sear(costed_dir, rover_project(waveform_probe_mcu("50"), "", 0.1), "--quiet --uart-frames");
  ASSERT_EQ(costed.exit_code, 0) << costed.err;
  const fs::path vcd = costed.dir / "rover.main.pins.vcd";
  EXPECT_EQ(sigrok_uart(vcd, "D18_loopback", 9600), "41 41 42 ");
  EXPECT_EQ(sigrok_uart(vcd, "D19_loopback", 9600), "41 41 42 ");
  EXPECT_EQ(sigrok_uart(vcd, "D16", 500000), hex_of(burst));
}

// Without --uart-frames a begun USART's pins show 'x' from the port's uart_begin on, with no edge
// after it: a flat idle line would say the port was silent while it sent "AAB" and 64 bytes; and
// the values leave the bytes out. Both headers say how to have them drawn; everything else is as
// with them, change for change.
TEST(Waveform, WithoutUartFramesABegunUsartsPinsShowUnknownAndNothingElseChanges) {
  TempDir dir, framed_dir;
  const SearRun run = run_sear(dir, rover_project(waveform_probe_mcu("0"), "", 0.1), "--quiet");
  const SearRun framed = run_sear(framed_dir, read_file(dir.path() / "project.xml"), "--quiet --uart-frames");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  ASSERT_EQ(framed.exit_code, 0) << framed.err;
  const std::string pins = run.file("rover.main.pins.vcd");
  EXPECT_NE(pins.find("$comment A begun USART's pins show x: sear run --uart-frames draws"), std::string::npos);
  // Each pin's lines after the header, as written: identifiers are '!' + the pin's number.
  const auto lines_of_pin = [](const std::string& vcd, int pin) {
    std::vector<std::string> out;
    const std::string body = vcd.substr(vcd.find("$enddefinitions"));
    for (const auto& line : lines_of(body))
      if (line.size() == 2 && line[1] == static_cast<char>('!' + pin)) out.push_back(line);
    return out;
  };
  EXPECT_EQ(lines_of_pin(pins, 18), (std::vector<std::string>{"z3", "x3"}));  // uart_begin(1) at 0
  EXPECT_EQ(lines_of_pin(pins, 19), (std::vector<std::string>{"z4", "x4"}));
  EXPECT_EQ(lines_of_pin(pins, 16), (std::vector<std::string>{"z1", "x1"}));  // uart_begin(2) at 60 ms
  EXPECT_EQ(read_vcd(pins).at("D16"), (std::vector<Change>{{0, kZ}}));
  // With the frames, the pins that carried bytes carry them (10 and more edges each) and the
  // silent RX2 (D17) idles high; every other pin, and the values' file, are the same.
  const Waves with = read_vcd(framed.file("rover.main.pins.vcd"));
  Waves without = read_vcd(pins);
  for (const char* usart : {"D16", "D18_loopback", "D19_loopback"}) EXPECT_GE(with.at(usart).size(), 10u) << usart;
  EXPECT_EQ(with.at("D17"), (std::vector<Change>{{0, kZ}, {60 * kMs, 1}}));
  for (const char* usart : {"D16", "D17", "D18_loopback", "D19_loopback"}) without.at(usart) = with.at(usart);
  EXPECT_EQ(without, with);
  const std::string values = run.file("rover.main.values.vcd");
  EXPECT_NE(values.find("$comment UART bytes are in the UART logs: sear run --uart-frames shows them here too $end"),
            std::string::npos);
  const Waves plain = read_vcd(values);
  Waves full = read_vcd(framed.file("rover.main.values.vcd"));
  // 'z' at 0, the 64 bytes, a 'z' between the two of each equal pair, and one after the last.
  EXPECT_EQ(full.at("uart2_tx").size(), 1u + 64u + 32u + 1u);
  for (const char* line : {"uart0_tx_console.rx", "uart0_rx_console.tx", "uart1_tx_loopback", "uart1_rx_loopback",
                           "uart2_tx", "uart2_rx", "uart3_tx", "uart3_rx"}) {
    EXPECT_EQ(plain.count(line), 0u) << line;
    EXPECT_EQ(full.erase(line), 1u) << line;
  }
  EXPECT_EQ(plain, full);
}

// Each pin is named after what is wired to it (a motor's inputs, a sensor's, a UART's far end, a
// jumper), with its number kept, so that a logic analyser's view reads as the wiring; GTKWave's
// reader keeps the names and sigrok's UART decoder finds a named pin.
TEST(Waveform, PinsAreNamedAfterWhatIsWiredToThem) {
  TempDir dir;
  const std::string mcu = std::string("    <mcu name=\"main\" console_uart=\"2\">\n      <firmware executable=\"") +
                          WAVEFORM_PROBE +
                          "\"/>\n      <uart port=\"1\" loopback=\"true\"/>\n"
                          "      <motor name=\"left\" pwm=\"3\" dir=\"12\" brake=\"9\"/>\n"
                          "      <hcsr04 name=\"sonar\" trig=\"24\" echo=\"10\" pos=\"0.15 0 0.05\"/>\n"
                          "      <gp2d12 name=\"ir_front\" adc=\"1\" pos=\"0.15 0 0.02\"/>\n    </mcu>\n";
  const SearRun run = run_sear(dir, rover_project(mcu, "", 0.1), "--quiet --uart-frames");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::vector<std::string> expected;
  for (int pin = 0; pin < SEAR_LINK_PINS; ++pin) expected.push_back("D" + std::to_string(pin));
  expected[3] = "D3_left.pwm";
  expected[9] = "D9_left.brake";
  expected[10] = "D10_sonar.echo";
  expected[12] = "D12_left.dir";
  expected[16] = "D16_console.rx";  // the console's RX is on the MCU's TX2
  expected[17] = "D17_console.tx";
  expected[18] = "D18_loopback";
  expected[19] = "D19_loopback";
  expected[24] = "D24_sonar.trig";
  expected[55] = "D55_ir_front.adc";  // A1
  std::vector<std::string> declared;
  for (const auto& line : lines_of(run.file("rover.main.pins.vcd"))) {
    std::istringstream words(line);
    std::string var, type, size, id, name;
    if (words >> var >> type >> size >> id >> name && var == "$var") declared.push_back(name);
  }
  EXPECT_EQ(declared, expected);
  const fs::path pins = run.dir / "rover.main.pins.vcd", values = run.dir / "rover.main.values.vcd";
  EXPECT_EQ(read_vcd(round_trip(pins, dir.path())), read_vcd(run.file("rover.main.pins.vcd")));
  const Waves duties = read_vcd(round_trip(values, dir.path()));
  // The probe's first pwm_write(3, 64), 5 ms in, on the value named after the pin's motor input.
  ASSERT_GE(duties.at("D3_pwm_left.pwm").size(), 2u);
  EXPECT_EQ(duties.at("D3_pwm_left.pwm")[1].value, 64);
  // Its delays add up to 5 ms; each of the six HAL calls up to the write (hal_init to the second
  // delay_us) adds at most the default 50 cycles at 16 MHz, 3.125 us.
  EXPECT_GE(duties.at("D3_pwm_left.pwm")[1].t, 5 * kMs);
  EXPECT_LE(duties.at("D3_pwm_left.pwm")[1].t, 5 * kMs + 6 * 3125);
  EXPECT_EQ(duties.count("uart2_tx_console.rx"), 1u);

  if (std::system("command -v sigrok-cli >/dev/null") != 0) {
    if (std::getenv("CI")) FAIL() << "sigrok-cli is missing (scripts/install-deps.sh installs it)";
    GTEST_SKIP() << "sigrok-cli is not installed";
  }
  std::string burst;
  for (int i = 0; i < 64; ++i) burst += static_cast<char>(i / 2);
  EXPECT_EQ(sigrok_uart(pins, "D16_console.rx", 500000), hex_of(burst));
}

// A byte's end is written in time order with the other changes, never past the MCU's stop or the
// run's end; different bytes back to back join, equal ones and those after an idle bit do not;
// and a byte that comes sooner than nine bit times after the last (a device sending faster than
// the port's baud) shows from its own time on, with no end between the two.
TEST(Waveform, ByteEndsFollowTheClockAndGiveWayToTheNextByte) {
  TempDir dir;
  const fs::path vcd = dir.path() / "w.vcd", values = dir.path() / "v.vcd";
  {
    BoundedFile pins_file(vcd.string(), 1 << 20, vcd_truncation_note(1 << 20));
    BoundedFile values_file(values.string(), 1 << 20, vcd_truncation_note(1 << 20));
    PinWaveform w(pins_file, values_file, "r.m");
    auto event = [&](std::int64_t t, sear_event_kind kind, int index, std::uint32_t value) {
      sear_event e{};
      e.time_ns = t;
      e.kind = static_cast<std::uint8_t>(kind);
      e.index = static_cast<std::uint8_t>(index);
      e.value = value;
      w.write(e);
    };
    event(0, SEAR_EVENT_UART_BEGIN, 0, 1000000);  // 1 us a bit: a byte shows for 9 us, a frame is 10
    event(0, SEAR_EVENT_UART_BEGIN, 1, 1000000);
    event(10000, SEAR_EVENT_UART_RX, 0, 0x55);  // until 19 us, but
    event(12000, SEAR_EVENT_UART_TX, 0, 0xAA);  // (until 21 us)
    event(15000, SEAR_EVENT_UART_RX, 0, 0x56);  // comes sooner: until 24 us
    event(22000, SEAR_EVENT_PIN, 5, 1);         // after the TX byte's end, which is written first
    event(30000, SEAR_EVENT_UART_RX, 1, 0x10);
    event(40000, SEAR_EVENT_UART_RX, 1, 0x11);  // back to back, different: joined
    event(50000, SEAR_EVENT_UART_RX, 1, 0x11);  // back to back, equal: apart
    event(61000, SEAR_EVENT_UART_RX, 1, 0x12);  // after an idle bit: apart
    w.finish(69999);  // the MCU stopped here: the last byte's end, and the RX 0x56's, are due
  }
  Waves waves = read_vcd(round_trip(vcd, dir.path()));
  waves.merge(read_vcd(round_trip(values, dir.path())));
  EXPECT_EQ(waves.at("uart0_rx"), (std::vector<Change>{{0, kZ}, {10000, 0x55}, {15000, 0x56}, {24000, kZ}}));
  EXPECT_EQ(waves.at("uart0_tx"), (std::vector<Change>{{0, kZ}, {12000, 0xAA}, {21000, kZ}}));
  EXPECT_EQ(waves.at("D5"), (std::vector<Change>{{0, kZ}, {22000, 1}}));
  EXPECT_EQ(waves.at("uart1_rx"),
            (std::vector<Change>{
                {0, kZ}, {30000, 0x10}, {40000, 0x11}, {49000, kZ}, {50000, 0x11}, {59000, kZ}, {61000, 0x12}}));
  const std::string text = read_file(values);
  EXPECT_LT(text.find("#21000"), text.find("#30000"));
  EXPECT_EQ(text.find("#70000"), std::string::npos);  // the last byte's end is past the stop
}

// The waveform declares a duty for exactly the pins the HAL lets pwm_write() drive, and a pulse
// width for those servo_write_us() accepts.
TEST(Waveform, ItsPwmAndServoPinsAreTheBoardsOwn) {
  for (int pin = 0; pin < SEAR_LINK_PINS; ++pin) {
    EXPECT_EQ(PinWaveform::has_pwm(pin), board_has_pwm(static_cast<std::uint8_t>(pin)) != 0) << pin;
    EXPECT_EQ(PinWaveform::has_servo(pin), board_has_servo(static_cast<std::uint8_t>(pin)) != 0) << pin;
  }
}

// The capture's waveform takes a MCU's events and each UART line's edges as streams, merged: the
// order must be what one stable sort of everything by time gives (ties in arrival order), also
// for a change that comes earlier than its stream's last, and taken in pieces as the run's time
// passes.
TEST(Waveform, EdgeStreamsGiveOneOrderByTimeThenArrival) {
  constexpr std::size_t kStreams = 9;
  EdgeStreams streams(kStreams);
  std::vector<sear_event> all;
  std::uint32_t lcg = 12345;
  std::int64_t t[kStreams] = {};
  for (std::uint32_t id = 0; id < 3000; ++id) {
    lcg = lcg * 1664525u + 1013904223u;
    const std::size_t s = (lcg >> 8) % kStreams;
    t[s] += (lcg >> 20) % 4;                                          // steps of 0..3 ns: many ties
    const std::int64_t time = (lcg >> 12) % 50 == 0 ? t[s] - 7 : t[s];  // now and then, out of order
    const sear_event e{time, id, SEAR_EVENT_PIN, 0, {0, 0}};
    streams.push(s, e);
    all.push_back(e);
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const sear_event& a, const sear_event& b) { return a.time_ns < b.time_ns; });
  std::vector<sear_event> taken;
  for (std::int64_t until = 0; taken.size() < all.size() && until < 100000; until += 97)
    streams.take_until(until, taken);
  ASSERT_EQ(taken.size(), all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    ASSERT_EQ(taken[i].value, all[i].value) << "at " << i << ", time " << all[i].time_ns;
    ASSERT_EQ(taken[i].time_ns, all[i].time_ns);
  }
}

// The waveform hands its file half a kilobyte of lines at a time: at the size limit the lines of
// such a write that fit still go in, whole, before the note; a binary file (no note) takes no part
// of the write that would cross its limit. Both stay within the limit.
TEST(Waveform, AFileAtItsLimitKeepsTheWholeLinesOfAWriteThatFit) {
  TempDir dir;
  const auto text = dir.path() / "text.vcd", binary = dir.path() / "raw.bin";
  const std::string note = "$comment cut $end\n";  // 18 bytes: room for 61 - 18 = 43 before it
  std::string lines;                                 // 8 changes of 6 bytes: 48
  for (int t = 2; t <= 9; ++t) lines += "#" + std::to_string(t) + "\n" + (t % 2 ? "1!\n" : "0!\n");
  {
    BoundedFile t(text.string(), 61, note), b(binary.string(), 8, "");
    t.write("#1\n1!\n");  // 6
    t.write(lines);        // 37 bytes of room left: 12 whole lines (36), not the 13th's first byte
    t.write("#10\n");
    b.write("12345");
    b.write("6789");
    EXPECT_TRUE(t.truncated());
    EXPECT_TRUE(b.truncated());
  }
  const std::string got = read_file(text);
  EXPECT_EQ(got, "#1\n1!\n" + lines.substr(0, 36) + note);
  EXPECT_LE(got.size(), 61u);
  // A binary file is filled to its limit, as the same bytes written one at a time would fill it
  // (a UART's raw capture is written in blocks).
  EXPECT_EQ(read_file(binary), "12345678");
}

}  // namespace
}  // namespace sear::test
