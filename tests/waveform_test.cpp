// The per-MCU VCD waveform read back by an independent reader: GTKWave's vcd2fst converts it to
// FST and fst2vcd writes it out again, and what the firmware did (tests/firmware/waveform_probe.c)
// is checked in that round-tripped text: pin levels, PWM duties, servo pulses and UART bytes at
// the times the firmware's delays and the baud rates put them.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>

#include "exporters/pin_waveform.hpp"
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
  const SearRun run = run_sear(dir, rover_project(mcu, "", 0.1), "--quiet");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  TempDir again_dir;
  const SearRun again = run_sear(again_dir, read_file(dir.path() / "project.xml"), "--quiet");
  EXPECT_EQ(again.file("rover.main.pins.vcd"), run.file("rover.main.pins.vcd"));  // deterministic
  const fs::path vcd = run.dir / "rover.main.pins.vcd";
  const Waves waves = read_vcd(round_trip(vcd, dir.path()));
  // The reader kept every change the file holds.
  EXPECT_EQ(waves, read_vcd(run.file("rover.main.pins.vcd")));

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
  EXPECT_EQ(waves.at("uart1_tx"), bytes("AAB", 0, 9600));
  EXPECT_EQ(waves.at("uart1_rx"), bytes("AAB", 0, 9600));
  EXPECT_EQ(waves.at("uart1_tx").size(), 6u);  // 'z' at 0, A, 'z', A, B, 'z'
  // 64 bytes back to back at 500 kbaud from 60 ms, each value twice: 20 us a frame.
  std::string burst;
  for (int i = 0; i < 64; ++i) burst += static_cast<char>(i / 2);
  EXPECT_EQ(waves.at("uart2_tx"), bytes(burst, 60 * kMs, 500000));
  for (const char* quiet : {"uart0_tx", "uart0_rx", "uart2_rx", "uart3_tx", "uart3_rx"})
    EXPECT_EQ(waves.at(quiet), (std::vector<Change>{{0, kZ}})) << quiet;
}

// A byte's end is written in time order with the other changes, never past the MCU's stop or the
// run's end; different bytes back to back join, equal ones and those after an idle bit do not;
// and a byte that comes sooner than nine bit times after the last (a device sending faster than
// the port's baud) shows from its own time on, with no end between the two.
TEST(Waveform, ByteEndsFollowTheClockAndGiveWayToTheNextByte) {
  TempDir dir;
  const fs::path vcd = dir.path() / "w.vcd";
  {
    BoundedFile file(vcd.string(), 1 << 20, vcd_truncation_note(1 << 20));
    PinWaveform w(file, "r.m");
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
  const Waves waves = read_vcd(round_trip(vcd, dir.path()));
  EXPECT_EQ(waves.at("uart0_rx"), (std::vector<Change>{{0, kZ}, {10000, 0x55}, {15000, 0x56}, {24000, kZ}}));
  EXPECT_EQ(waves.at("uart0_tx"), (std::vector<Change>{{0, kZ}, {12000, 0xAA}, {21000, kZ}}));
  EXPECT_EQ(waves.at("D5"), (std::vector<Change>{{0, kZ}, {22000, 1}}));
  EXPECT_EQ(waves.at("uart1_rx"),
            (std::vector<Change>{
                {0, kZ}, {30000, 0x10}, {40000, 0x11}, {49000, kZ}, {50000, 0x11}, {59000, kZ}, {61000, 0x12}}));
  const std::string text = read_file(vcd);
  EXPECT_LT(text.find("#21000"), text.find("#22000"));
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

}  // namespace
}  // namespace sear::test
