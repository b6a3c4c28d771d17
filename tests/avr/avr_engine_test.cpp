// The AVR engine (engines/avr): register-level firmware of our own runs in lockstep on libsimavr's
// ATmega2560 and its timing is held to the datasheet's arithmetic at 16 MHz (62.5 ns a cycle);
// hostile images are reported as the chip would fail; the same run twice gives the same bytes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include "devices/hcsr04.h"
#include "devices/sharp_gp2d12.h"
#include "firmware_run.hpp"
#include "model_run.hpp"

namespace sear::test {
namespace {

constexpr double kCycleNs = 1e9 / 16e6;  // 62.5 ns

std::string avr_mcu(const std::string& firmware_sources, const std::string& wiring = "") {
  return std::string("    <mcu name=\"main\" engine=\"avr\" clock_hz=\"16e6\">\n      <firmware sources=\"") +
         firmware_sources + "\"/>\n" + wiring + "    </mcu>\n";
}

std::string test_firmware(const char* name) { return std::string(AVR_TEST_FIRMWARE) + "/" + name; }

// The times of a pin's level changes in the run's VCD (1 ns units), 'z' left out.
std::vector<std::int64_t> edges(const SearRun& run, int pin) {
  std::vector<std::int64_t> t;
  for (const auto& c : vcd_changes(run.file("rover.main.pins.vcd"), vcd_id_of_pin(pin)))
    if (c.value == '0' || c.value == '1') t.push_back(c.time);
  return t;
}

// (time in ns, byte) of each "tx" or "rx" line of a UART log ("S.NNNNNNNNN tx 4c").
std::vector<std::pair<std::int64_t, int>> uart_bytes(const std::string& log, const std::string& direction) {
  std::vector<std::pair<std::int64_t, int>> bytes;
  const std::regex line("^(\\d+)\\.(\\d{9}) " + direction + " ([0-9a-f]{2})$");
  std::smatch m;
  for (const auto& l : lines_of(log))
    if (std::regex_match(l, m, line))
      bytes.emplace_back(std::stoll(m[1]) * 1000000000 + std::stoll(m[2]), std::stoi(m[3], nullptr, 16));
  return bytes;
}

// A UART capture in SEAR's format whose `tx` bytes arrive one every `spacing_ns` from `first_ns`.
std::string capture_of(const std::string& bytes, std::int64_t first_ns, std::int64_t spacing_ns) {
  std::string capture = "# SEAR UART capture: bytes for the firmware, 8N1\n";
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    const std::int64_t t = first_ns + static_cast<std::int64_t>(i) * spacing_ns;
    char line[64];
    std::snprintf(line, sizeof line, "%lld.%09lld tx %02x\n", static_cast<long long>(t / 1000000000),
                  static_cast<long long>(t % 1000000000), static_cast<unsigned char>(bytes[i]));
    capture += line;
  }
  return capture;
}

TEST(AvrEngine, Timer1CompareInterruptTogglesAPinEvery16000Cycles) {
  TempDir dir;
  const auto run = run_sear(dir, rover_project(avr_mcu(test_firmware("timer1_toggle.c")), "", 0.03));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto t = edges(run, 13);
  // The first change is the pin going out LOW (DDRB); then one toggle per millisecond from the
  // first compare match on: 29 in 30 ms.
  ASSERT_GE(t.size(), 29u) << run.file("rover.main.pins.vcd").substr(0, 400);
  for (std::size_t i = 2; i < t.size(); ++i) {
    // (OCR1A + 1) * 8 = 16000 cycles = 1 ms. The interrupt is taken after the instruction in
    // progress (the idle loop's 2-cycle RJMP), so an edge may move by one cycle; the VCD's
    // nanoseconds are the cycle's time rounded down.
    EXPECT_NEAR(static_cast<double>(t[i] - t[i - 1]), 1e6, kCycleNs + 1) << "edge " << i;
  }
  // What the engine measured (summary.json, avr_engines): the one ISR is TIMER1_COMPA, vector 17
  // (datasheet table 14-1), entered once per toggle; the chip never sleeps, so it is always busy;
  // the idle loop spends nearly every cycle in main.
  const auto report = nlohmann::json::parse(run.file("summary.json"))["avr_engines"]["rover.main"];
  ASSERT_TRUE(report.is_object()) << run.file("summary.json");
  EXPECT_EQ(report["cycles"].get<long long>(), 480000);  // 30 ms at 16 MHz, the report's last quantum
  EXPECT_DOUBLE_EQ(report["cpu_load"].get<double>(), 1.0);
  ASSERT_EQ(report["isrs"].size(), 1u) << report.dump();
  EXPECT_EQ(report["isrs"][0]["vector"], 17);
  EXPECT_EQ(report["isrs"][0]["entries"].get<std::size_t>(), t.size() - 1);
  // Pending to running: at most the idle loop's RJMP (2 cycles); simavr enters in 0 cycles.
  EXPECT_LE(report["isrs"][0]["latency_cycles"]["max"].get<int>(), 2);
  EXPECT_EQ(report["top_functions"][0]["name"], "main");
  // Interrupts are held off only while the ISR runs (the chip clears I on entry, RETI sets it):
  // the longest stretch is one run of it, from its vector. The ISR takes the same path each time,
  // so each run is its mean; the vector's cycles end as RETI begins (simavr's running flag), the
  // I flag is set once RETI has run, 5 cycles on a part with a 3-byte PC (instruction set manual).
  const double isr_run = report["isrs"][0]["cycles"].get<double>() / report["isrs"][0]["entries"].get<double>();
  EXPECT_EQ(report["interrupts_off"]["from"], "__vector_17") << report.dump();
  EXPECT_DOUBLE_EQ(report["interrupts_off"]["longest_cycles"].get<double>(), isr_run + 5) << report.dump();
  // The ISR's frame: a return address (3 bytes on this 3-byte-PC part) and a few saved registers.
  EXPECT_GE(report["stack"]["worst_depth_bytes"].get<int>(), 3);
  EXPECT_LE(report["stack"]["worst_depth_bytes"].get<int>(), 32);
}

// Timer1 in phase-correct 8-bit PWM at clk/64, as the Arduino core and SEAR's HAL leave timers
// 1..5: the chip counts 0..255..0 and overflows every 2 * 255 * 64 = 32640 cycles (datasheet
// 17.9.4), 14.7 times in 30 ms. simavr 1.6 counts single-slope, so the engine gives the mode its
// TOP with 256 counts a period, 16384 cycles, 29.3 times in 30 ms: at most twice the chip's rate.
// Left undefined, as simavr leaves the mode, the timer overflowed at every count (7500 times).
TEST(AvrEngine, APhaseCorrectTimerOverflowsOncePerItsPeriodNotEveryCount) {
  TempDir dir;
  const auto run = run_sear(dir, rover_project(avr_mcu(test_firmware("timer1_phase_correct.c")), "", 0.03));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto report = nlohmann::json::parse(run.file("summary.json"))["avr_engines"]["rover.main"];
  ASSERT_EQ(report["isrs"].size(), 1u) << report.dump();
  EXPECT_EQ(report["isrs"][0]["vector"], 20);  // TIMER1_OVF, datasheet table 14-1
  const auto entries = report["isrs"][0]["entries"].get<int>();
  EXPECT_GE(entries, 14);
  EXPECT_LE(entries, 30);
}

TEST(AvrEngine, AdcFreeRunningInterruptEvery1664CyclesReadsTheRangersVolts) {
  TempDir dir;
  // A GP2D12 without noise seeing nothing: its output is the model's for no target.
  const auto run = run_sear(dir, rover_project(avr_mcu(test_firmware("adc_free_running.c"),
                                                       "      <gp2d12 name=\"ir\" adc=\"0\" pos=\"0.15 0 0.02\" noise_v=\"0\"/>\n"),
                                               "", 0.05));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto t = edges(run, 12);
  ASSERT_GE(t.size(), 100u);
  // Free running: 13 ADC clocks of 128 cycles each (datasheet 26.4) = 1664 cycles = 104 us;
  // the ISR's entry moves by up to the longest instruction of the idle loop (LDS, 2 cycles).
  for (std::size_t i = 2; i < t.size(); ++i)
    EXPECT_NEAR(static_cast<double>(t[i] - t[i - 1]), 104000.0, 2 * kCycleNs + 1) << "conversion " << i;
  std::smatch m;
  const std::string console = run.file("rover.main.console.log");
  ASSERT_TRUE(std::regex_search(console, m, std::regex("adc (\\d{4})"))) << console;
  const double volts = gp2d12_sample_v(INFINITY, 0, 0, 0.0);
  // simavr takes the input in whole millivolts: at most 0.5 mV = 0.1 LSB off the volts' code.
  EXPECT_NEAR(std::stoi(m[1]), static_cast<double>(adc_code(volts, 5.0)), 1.0) << volts << " V";
}

TEST(AvrEngine, UsartReceiveInterruptEchoesEachByteOneFrameAfterIt) {
  TempDir dir;
  const char* word = "SEAR";
  dir.write("bytes.log", capture_of(word, 10000000, 5000000));
  const auto run = run_sear(
      dir, rover_project(avr_mcu(test_firmware("usart_echo.c"), "      <uart port=\"0\" receive=\"bytes.log\"/>\n"), "",
                         0.04));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string log = run.file("rover.main.uart0.log");
  const auto rx = uart_bytes(log, "rx"), tx = uart_bytes(log, "tx");
  ASSERT_EQ(rx.size(), 4u) << log;
  ASSERT_EQ(tx.size(), 4u) << log;
  // UBRR0 = 103: 16 (103 + 1) = 1664 cycles a bit, 10 bits = 16640 cycles = 1.04 ms a frame.
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(rx[i].second, word[i]);
    EXPECT_EQ(tx[i].second, word[i] + 1);
    // The byte is written to UDR0 by the ISR a few dozen cycles after RXC: interrupt entry,
    // prologue, one load and one store; the frame then takes its 1.04 ms exactly.
    const double after = static_cast<double>(tx[i].first - rx[i].first) - 1040000.0;
    EXPECT_GE(after, 0.0) << i;
    EXPECT_LE(after, 64 * kCycleNs) << i;
  }
}

// Six bytes back to back at 9600 baud while the firmware reads nothing for 20 ms: the chip keeps
// two in its receive buffer and one in its shift register, and loses the rest with DOR0 set until
// UDR0 is read (simavr alone would keep all six: its FIFO holds 64).
TEST(AvrEngine, UsartOverrunKeepsThreeBytesAndSetsDorUntilRead) {
  TempDir dir;
  dir.write("bytes.log", capture_of("ABCDEF", 1000000, 1040000));  // back to back: 1.04 ms a frame
  const auto run = run_sear(
      dir, rover_project(avr_mcu(test_firmware("usart_overrun.c"), "      <uart port=\"0\" receive=\"bytes.log\"/>\n"),
                         "", 0.03));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string log = run.file("rover.main.uart0.log");
  const auto rx = uart_bytes(log, "rx"), tx = uart_bytes(log, "tx");
  ASSERT_EQ(rx.size(), 6u) << log;  // all six reached the pin
  std::string answer;
  for (const auto& b : tx) answer += static_cast<char>(b.second);
  // DOR0 set; A and B from the buffer, C from the shift register; DOR0 clear once read.
  EXPECT_EQ(answer, "!ABC.") << log;
  const auto report = nlohmann::json::parse(run.file("summary.json"))["avr_engines"]["rover.main"];
  EXPECT_EQ(report["usart_overruns"], nlohmann::json::parse("[3, 0, 0, 0]")) << report.dump();
}

// Three bytes held while the receive interrupt is off are taken back to back once it is on:
// RXC0 stays set while a byte waits (UCSRnA in the datasheet), so the ISR runs again right after
// its RETI. simavr 1.6 alone lets a byte be read only a frame after the one before (1.04 ms at
// 9600 baud), and a firmware held up once (an SPI read in another ISR) never catches up with a
// fast stream: every later delay overruns.
TEST(AvrEngine, UsartReceiveBacklogIsTakenBackToBack) {
  TempDir dir;
  dir.write("bytes.log", capture_of("ABC", 1000000, 1040000));  // back to back: 1.04 ms a frame
  const auto run = run_sear(
      dir, rover_project(avr_mcu(test_firmware("usart_backlog.c"), "      <uart port=\"0\" receive=\"bytes.log\"/>\n"),
                         "", 0.02));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string console = run.file("rover.main.console.log");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(console, m, std::regex("g (\\d+) (\\d+)"))) << console;
  // From one entry's TCNT1 read to the next (avr-gcc -Os): the rest of the ISR's body (25 cycles),
  // its epilogue (20) and RETI (5), one instruction of the main loop (up to 2), the interrupt's
  // entry with a 3-byte PC (5) and the vector's JMP (3), the prologue (21): 81 cycles, 10 ticks of
  // 8 or 11 as the prescaler's phase falls; 12 allows a longer main-loop instruction. A frame
  // would be 16640 cycles, 2080 ticks.
  EXPECT_LE(std::stoi(m[1].str()), 12) << console;
  EXPECT_LE(std::stoi(m[2].str()), 12) << console;
}

TEST(AvrEngine, TwiAndSpiMastersReadTheImusWhoAmIByRegisters) {
  TempDir dir;
  const auto run = run_sear(dir, rover_project(avr_mcu(test_firmware("imu_registers.c"),
                                                       "      <mpu6050 name=\"imu_i2c\" address=\"0x68\" pos=\"0 0 0.05\"/>\n"
                                                       "      <mpu6000 name=\"imu_spi\" cs=\"53\" pos=\"0 0 0.05\"/>\n"),
                                               "", 0.02));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // WHO_AM_I reads 0x68 on both parts (MPU-6000/6050 register map, register 117).
  EXPECT_NE(run.file("rover.main.console.log").find("twi 68 spi 68"), std::string::npos)
      << run.file("rover.main.console.log") << run.file("rover.main.host.log");
}

// Every TWI step as the datasheet's status table has it (24-3, 24-4), for a master that polls
// TWINT at once after each TWCR write, as the HAL, Wire and most drivers do; and bytes that take
// the bus clock's time. simavr 1.6 alone gives 28h for an acknowledged SLA+W and 30h for a refused
// one (data statuses), never clears TWINT when the firmware writes it one (the next poll sees the
// last step's flag), and paces a TWI byte at 9 us and an SPI byte at 100 us whatever the clock.
TEST(AvrEngine, TwiStatusesAndBusByteTimesAreTheDatasheets) {
  TempDir dir;
  const auto run = run_sear(dir, rover_project(avr_mcu(test_firmware("bus_steps.c"),
                                                       "      <hmc5883l name=\"compass\" pos=\"0 0 0.1\"/>\n"
                                                       "      <mpu6000 name=\"imu_spi\" cs=\"53\" pos=\"0 0 0.05\"/>\n"),
                                               "", 0.02));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string console = run.file("rover.main.console.log");
  const std::regex answer("twi ((?:[0-9A-F]{2} )+)h ([0-9A-F ]+) t (\\d+) spi ([0-9A-F]{2}) t (\\d+)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(console, m, answer)) << console << run.file("rover.main.host.log");
  // START, SLA+W ACK, data ACK, repeated START, SLA+R ACK, data ACK, ACK, NACK (the last byte);
  // then at 0x33: START, SLA+W NACK; START, SLA+R NACK.
  EXPECT_EQ(m[1].str(), "08 18 28 10 40 50 50 58 08 20 08 48 ");
  EXPECT_EQ(m[2].str(), "48 34 33");  // the HMC5883L's identification, "H43"
  // A byte and its acknowledge are 9 SCL periods of 16 + 2 TWBR = 40 cycles; the measurement adds
  // its own instructions (the TWCR store, up to one more 5-cycle poll, the TCNT1 reads): under 16.
  const int twi_cycles = std::stoi(m[3].str());
  EXPECT_GE(twi_cycles, 9 * 40);
  EXPECT_LT(twi_cycles, 9 * 40 + 16);
  EXPECT_EQ(m[4].str(), "68");  // WHO_AM_I (MPU-6000 register map, register 117)
  // 8 SCK periods of 16 cycles at clk/16, and the same under 16 for the measuring.
  const int spi_cycles = std::stoi(m[5].str());
  EXPECT_GE(spi_cycles, 8 * 16);
  EXPECT_LT(spi_cycles, 8 * 16 + 16);
}

// The echo pulses (rise, fall) on ECHO (pin 10) of a run of echo_ping.c, each with the fall of the
// TRIG pulse (pin 24) that started it.
struct Echo {
  std::int64_t trig_fell, rose, fell;
};
std::vector<Echo> echoes(const SearRun& run) {
  std::vector<Echo> found;
  const auto trig = vcd_changes(run.file("rover.main.pins.vcd"), vcd_id_of_pin(24));
  const auto echo = vcd_changes(run.file("rover.main.pins.vcd"), vcd_id_of_pin(10));
  for (std::size_t k = 0; k + 1 < echo.size(); ++k) {
    if (echo[k].value != '1' || echo[k + 1].value != '0') continue;
    std::int64_t trig_fell = -1;
    for (const auto& c : trig)
      if (c.value == '0' && c.time < echo[k].time) trig_fell = c.time;
    found.push_back({trig_fell, echo[k].time, echo[k + 1].time});
  }
  return found;
}

// A pin a device drives reaches the waveform from either engine (a PIN_DRIVEN event at the
// device's own time): the same firmware pings the HC-SR04 facing a wall on both, and pins.vcd
// holds the same echoes. The device starts an echo HCSR04_ECHO_DELAY_NS after it sees TRIG fall
// and holds it for the round trip, so each pulse is compared against its own TRIG fall, which
// the engines place differently (the HAL's cost model against the chip's cycles). The AVR engine
// sees TRIG fall at the cycle of the PORT write, the time its VCD shows, so delay and width agree
// to the VCD's nanosecond, the device's noise being drawn in the same order from the same seed.
TEST(AvrEngine, TheEchoADeviceDrivesIsInBothEnginesWaveforms) {
  const std::string sonar = "      <hcsr04 name=\"sonar\" trig=\"24\" echo=\"10\" pos=\"0.15 0 0.05\"/>\n";
  const std::string wall = "    <wall name=\"target\" from=\"1.2 -2\" to=\"1.2 2\" height=\"0.5\" thickness=\"0.1\"/>\n";
  const std::string native_mcu = std::string("    <mcu name=\"main\">\n      <firmware sources=\"") +
                                 test_firmware("echo_ping.c") + "\"/>\n" + sonar + "    </mcu>\n";
  TempDir native_dir, avr_dir;
  const auto native = run_sear(native_dir, rover_project(native_mcu, wall, 0.8));
  const auto avr = run_sear(avr_dir, rover_project(avr_mcu(test_firmware("echo_ping.c"), sonar), wall, 0.8));
  ASSERT_EQ(native.exit_code, 0) << native.err;
  ASSERT_EQ(avr.exit_code, 0) << avr.err;
  const auto a = echoes(native), b = echoes(avr);
  // A ping each 60 ms after the last ~6 ms echo, over 0.8 s: 12; the engines' pings drift apart
  // by the cost model, so one may lose the ping cut off at the run's end.
  ASSERT_GE(a.size(), 11u);
  ASSERT_NEAR(static_cast<double>(b.size()), static_cast<double>(a.size()), 1.0);
  for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k) {
    ASSERT_GT(b[k].trig_fell, 0) << "echo " << k;
    EXPECT_EQ(b[k].rose - b[k].trig_fell, HCSR04_ECHO_DELAY_NS) << "echo " << k;
    EXPECT_EQ(a[k].rose - a[k].trig_fell, HCSR04_ECHO_DELAY_NS) << "echo " << k;
    EXPECT_EQ(b[k].fell - b[k].rose, a[k].fell - a[k].rose) << "echo " << k;
    // The wall's face (1.2 m less half its 0.1 m) is 1.0 m from the sensor (0.15 m ahead of the
    // rover's centre): 100 cm of HCSR04_ECHO_NS_PER_CM, give or take the model's range noise,
    // clipped at HCSR04_NOISE_CLIP_SD of HCSR04_NOISE_SD_M.
    EXPECT_NEAR(static_cast<double>(b[k].fell - b[k].rose), 100.0 * HCSR04_ECHO_NS_PER_CM,
                HCSR04_NOISE_CLIP_SD * HCSR04_NOISE_SD_M * 100.0 * HCSR04_ECHO_NS_PER_CM)
        << "echo " << k;
  }
}

// A quadrature encoder on pin-change pins: the motor turns on timer3's PWM, every edge of either
// channel raises a pin-change interrupt, and the ISR's answer on pin 22 follows each edge by the
// datasheet's instruction times plus what simavr 1.6 does differently. The channels are on pins
// a and b, the vector is `vector` (counted from 0, as simavr and the report count), and the naked
// ISR in `firmware` toggles pin 22 once per edge.
void encoder_edges_are_answered_within_their_cycles(const char* firmware, int a, int b, int vector) {
  const std::string wiring = "      <motor name=\"left\" pwm=\"3\" dir=\"12\"/>\n"
                             "      <quadrature_encoder name=\"enc\" wheel=\"left\" a=\"" +
                             std::to_string(a) + "\" b=\"" + std::to_string(b) + "\" cycles_per_rev=\"90\"/>\n";
  TempDir dir;
  const auto run = run_sear(dir, rover_project(avr_mcu(test_firmware(firmware), wiring), "", 0.3));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::vector<std::int64_t> encoder;
  for (const int pin : {a, b})
    for (const auto t : edges(run, pin))
      if (t > 0) encoder.push_back(t);  // t = 0: the levels the encoder starts at, not edges
  std::sort(encoder.begin(), encoder.end());
  std::vector<std::int64_t> answers = edges(run, 22);
  answers.erase(answers.begin());  // the pin going out LOW (DDRA)
  // The motor at 200/255 duty of its 6 V turns the free wheel at up to 125 rpm, 2.1 turns a
  // second of 360 edges (90 cycles, both edges of both channels); a quarter turn in 0.3 s is far
  // below that even counting the spin-up, and far above a wheel that never moved.
  ASSERT_GE(encoder.size(), 90u);
  ASSERT_EQ(answers.size(), encoder.size());
  for (std::size_t k = 0; k < encoder.size(); ++k) {
    // The edge is applied at the first instruction boundary at or after its time (the idle loop's
    // RJMP: 2 cycles, so up to 1 cycle late, plus under a cycle of rounding to the clock); one more
    // RJMP runs before simavr takes the interrupt, in 0 cycles (the chip takes 5 with a 3-byte PC);
    // the vector's JMP takes 3; the pin changes as the SBI starts. From 5 to under 7 cycles, 312.5
    // to 437.5 ns, which the VCD's whole nanoseconds, rounded down, show as 312 to 437.
    const std::int64_t delay = answers[k] - encoder[k];
    EXPECT_GE(delay, static_cast<std::int64_t>(5 * kCycleNs)) << "edge " << k << " at " << encoder[k];
    EXPECT_LE(delay, static_cast<std::int64_t>(7 * kCycleNs)) << "edge " << k << " at " << encoder[k];
  }
  const auto report = nlohmann::json::parse(run.file("summary.json"))["avr_engines"]["rover.main"];
  ASSERT_EQ(report["isrs"].size(), 1u) << report.dump();
  EXPECT_EQ(report["isrs"][0]["vector"], vector);
  EXPECT_EQ(report["isrs"][0]["entries"].get<std::size_t>(), encoder.size());
  EXPECT_EQ(report["isrs"][0]["latency_cycles"]["max"].get<int>(), 2);  // that one RJMP
}

TEST(AvrEngine, PinChangeInterruptAnswersEachEncoderEdgeWithinItsCycles) {
  // PCINT0: vector 10 of datasheet table 14-1, counted from 1.
  encoder_edges_are_answered_within_their_cycles("pcint_encoder.c", 10, 11, 9);
}

// PCINT2 (A8..A15), vector 12 of table 14-1: simavr 1.6 has no such interrupt on its ATmega2560,
// so without the engine's an MPU-6000's data-ready pin on A9 is never heard (the reference
// rover's IMU).
TEST(AvrEngine, PinChangeInterruptOnA8ToA15AnswersEachEncoderEdgeWithinItsCycles) {
  encoder_edges_are_answered_within_their_cycles("pcint2_encoder.c", 62, 63, 11);
}

// The wiring report on this engine: what the registers show the firmware read. It converts ADC
// channel 0 and reads PINB; a ranger on channel 1 and a switch on pin 22 (PA0) it never reads.
TEST(AvrEngine, TheWiringReportNamesInputsTheFirmwareNeverRead) {
  const std::string wiring =
      "      <gp2d12 name=\"ir_read\" adc=\"0\" pos=\"0.15 0 0.02\"/>\n"
      "      <gp2d12 name=\"ir_unread\" adc=\"1\" pos=\"0.15 0.05 0.02\"/>\n"
      "      <bump name=\"bump_read\" pin=\"10\" pos=\"0.14 0 -0.01\" width=\"0.18\" reach=\"0.02\"/>\n"
      "      <bump name=\"bump_unread\" pin=\"22\" pos=\"-0.14 0 -0.01\" width=\"0.18\" reach=\"0.02\"/>\n";
  TempDir dir;
  const auto run = run_sear(dir, rover_project(avr_mcu(test_firmware("reads_some.c"), wiring), "", 0.05));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto notes = nlohmann::json::parse(run.file("summary.json"))["wiring"];
  std::vector<std::string> unused;
  for (const auto& note : notes)
    if (note["kind"] == "unused wiring") unused.push_back(note["device"].get<std::string>());
  std::sort(unused.begin(), unused.end());
  EXPECT_EQ(unused, (std::vector<std::string>{"bump_unread", "ir_unread"})) << notes.dump(2);
}

TEST(AvrEngine, TheSameRunTwiceGivesTheSameBytes) {
  TempDir dir;
  const std::string project =
      rover_project(avr_mcu(test_firmware("adc_free_running.c"), "      <gp2d12 name=\"ir\" adc=\"0\" pos=\"0.15 0 0.02\"/>\n"),
                    "", 0.03);
  TempDir a_dir, b_dir;
  const auto a = run_sear(a_dir, project), b = run_sear(b_dir, project);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  for (const char* file : {"rover.main.pins.vcd", "rover.main.console.log", "rover.main.uart0.log"})
    EXPECT_TRUE(a.file(file) == b.file(file)) << file << " differs between two runs";
}

// The engine hands simavr local runs of instructions (engines/avr/local_runs.h) and keeps every
// observation exact: a run gives the same bytes as one instruction per call
// (SEAR_AVR_SINGLE_STEP), in every file the run writes and in its summary but for the summary's
// wall-clock figures (wall_time_s, real_time_factor, step_wall_us) and summary.txt, which prints
// two of them. The reference rover's AVR build reaches every device kind (the LMS200 from 2 s, at
// 500 kbaud from 2.4 s, SPI, TWI, pin-change and timer interrupts, the ADC); the avoider spends
// its cycles in delay loops that take interrupts; both write the engine's profile (per-function
// cycles, interrupt latency, interrupts-off stretches, the stack's low mark).
class LocalRuns : public ::testing::TestWithParam<const char*> {};

TEST_P(LocalRuns, ChangeNoByteOfWhatTheRunWrites) {
  const auto run = [](const char* single_step) {
    TempDir dir;
    if (single_step) setenv("SEAR_AVR_SINGLE_STEP", single_step, 1);
    else unsetenv("SEAR_AVR_SINGLE_STEP");
    const std::string cmd = std::string(SEAR_BINARY) + " run " SEAR_ASSET_DIR "/projects/" + GetParam() +
                            " --engine avr --no-plots --quiet --duration 2.6 -o " + (dir.path() / "out").string() +
                            " 2>" + (dir.path() / "err").string();
    const int status = std::system(cmd.c_str());
    unsetenv("SEAR_AVR_SINGLE_STEP");
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << read_file(dir.path() / "err");
    std::map<std::string, std::string> files;
    for (const auto& f : std::filesystem::directory_iterator(dir.path() / "out"))
      if (f.path().filename() != "summary.txt") files[f.path().filename().string()] = read_file(f.path());
    auto summary = nlohmann::json::parse(files["summary.json"]);
    summary.erase("wall_time_s");
    summary.erase("real_time_factor");
    summary.erase("step_wall_us");
    files["summary.json"] = summary.dump(1);
    return files;
  };
  const auto single = run("1"), runs = run(nullptr);
  ASSERT_TRUE(single.count("rover.main.avr.json")) << "no engine report";
  ASSERT_EQ(single.size(), runs.size());
  for (const auto& [name, bytes] : single) {
    ASSERT_TRUE(runs.count(name)) << name;
    EXPECT_TRUE(runs.at(name) == bytes) << name << " differs with local runs";
  }
}

INSTANTIATE_TEST_SUITE_P(Projects, LocalRuns, ::testing::Values("default.xml", "avoider_hills.xml"));

// What the projects above never do inside a local run: turn interrupts off and on by stores to
// SREG (STS and OUT, not CLI and SEI) and take the stack to a new low by stores to SPH:SPL and
// PUSHes (tests/avr/firmware/sreg_sp_stores.c, once). Interrupts are off for the ten NOPs and
// the OUT after the store, one cycle each (instruction set manual); the stack's low mark is
// main's return address (3 bytes on this 3-byte-PC part), the 40 bytes it moves down and the 2
// it pushes. Runs that went on past the stores (the write hooks taken out) saw no stretch at all
// and 3 bytes.
TEST(AvrEngine, StoresToSregAndTheStackPointerAreSeenAtTheirCycleInALocalRun) {
  TempDir dir;
  const auto run = run_sear(dir, rover_project(avr_mcu(test_firmware("sreg_sp_stores.c")), "", 0.01), "--no-plots");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto report = nlohmann::json::parse(run.file("rover.main.avr.json"));
  EXPECT_EQ(report["interrupts_off"]["longest_cycles"].get<int>(), 11) << report.dump();
  EXPECT_EQ(report["interrupts_off"]["from"].get<std::string>().rfind("main+", 0), 0u) << report.dump();
  EXPECT_EQ(report["stack"]["worst_depth_bytes"].get<int>(), 45) << report.dump();
}

// Where a local run must end when the path to it is one-cycle instructions all the way
// (tests/avr/firmware/run_edges.c): after a CLI, so that interrupts are off for the ten NOPs and
// the SEI, one cycle each (instruction set manual); after a jump out of a function, so that each
// function's cycles are its own: 1000 calls of tail_jump (two NOPs and an RJMP, 1 + 1 + 2 cycles)
// and of fifteen_cycles (ten NOPs and a RET, 10 + 5 on this 3-byte-PC part). A run one
// instruction longer saw 10 cycles off; runs across the jump gave about 14000 and 5000.
TEST(AvrEngine, LocalRunsEndAfterACliAndAtAFunctionsEdge) {
  TempDir dir;
  const auto run = run_sear(dir, rover_project(avr_mcu(test_firmware("run_edges.c")), "", 0.01), "--no-plots");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto report = nlohmann::json::parse(run.file("rover.main.avr.json"));
  EXPECT_EQ(report["interrupts_off"]["longest_cycles"].get<int>(), 11) << report.dump();
  std::map<std::string, long> cycles;
  for (const auto& f : report["top_functions"]) cycles[f["name"].get<std::string>()] = f["cycles"].get<long>();
  EXPECT_EQ(cycles["tail_jump"], 4000) << report.dump();
  EXPECT_EQ(cycles["fifteen_cycles"], 15000) << report.dump();
}

// The bundled avoider's AVR build, unmodified, in its own world (assets/projects/avoider_hills.xml,
// as tests/avoider_test.cpp runs it natively): it reports ready, drives, and touches no wall.
TEST(AvrEngine, TheAvoidersAvrBuildDrivesItsWorldWithoutTouchingAWall) {
  TempDir dir;
  const auto out = dir.path() / "out";
  const std::string cmd = std::string(SEAR_BINARY) + " run " SEAR_ASSET_DIR "/projects/avoider_hills.xml --engine avr " +
                          "--quiet --duration 20 -o " + out.string() + " 2>" + (dir.path() / "err").string();
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << read_file(dir.path() / "err");
  const auto summary = nlohmann::json::parse(read_file(out / "summary.json"));
  EXPECT_DOUBLE_EQ(summary["sim_time_s"].get<double>(), 20.0);
  for (const auto& c : summary["collision_events"])
    EXPECT_EQ(c["other"].get<std::string>().find("_wall"), std::string::npos) << c.dump();
  // At CRUISE (150/255) the rover makes about 0.5 m/s; 20 s of it, turns and all, is well over 4 m.
  EXPECT_GT(summary["robots"][0]["distance_m"].get<double>(), 4.0);
  EXPECT_NE(read_file(out / "rover.main.console.log").find("avoider: ready"), std::string::npos);
}

// SICK's telegram CRC (telegram listing, "CRC calculation"), to find whole scans in a capture.
std::uint16_t sick_crc(const std::vector<int>& t, std::size_t from, std::size_t n) {
  std::uint16_t crc = 0;
  int previous = 0;
  for (std::size_t i = from; i < from + n; ++i) {
    crc = (crc & 0x8000u) ? static_cast<std::uint16_t>(((crc & 0x7FFFu) << 1) ^ 0x8005u)
                          : static_cast<std::uint16_t>(crc << 1);
    crc = static_cast<std::uint16_t>(crc ^ ((previous << 8) | t[i]));
    previous = t[i];
  }
  return crc;
}

// The reference rover (the default project: rover.c on an LMS200, an MPU-6000 over SPI, an
// HMC5883L over TWI, a GPS) built for the ATmega2560 brings everything up and reaches its drive
// loop with the scanner's scans in it. 3.5 s: the LMS200's power-up telegram comes at 2 s, its
// configuration and the GPS's take to 2.4 s, and the second report, the first after a scan was
// looked at, comes at 3.4 s.
TEST(AvrEngine, TheReferenceRoversAvrBuildBringsUpItsSensorsAndSeesItsScans) {
  TempDir dir;
  const auto out = dir.path() / "out";
  const std::string cmd = std::string(SEAR_BINARY) + " run " SEAR_ASSET_DIR "/projects/default.xml --engine avr " +
                          "--quiet --duration 3.5 -o " + out.string() + " 2>" + (dir.path() / "err").string();
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << read_file(dir.path() / "err");
  const std::string console = read_file(out / "rover.main.console.log");
  // The HMC5883L answered at 0x1E with "H43" and took its settings, over the HAL's TWI master.
  EXPECT_EQ(console.find("compass: no HMC5883L"), std::string::npos) << console;
  EXPECT_EQ(console.find("imu: no MPU-6000"), std::string::npos) << console;
  // The LMS200 answered at its power-up 9600 baud, moved to 500 kbaud (UBRR1 3 with U2X: exactly
  // 500000) and took the 180 degree, 0.5 degree variant.
  for (const char* said : {"lms: power-up telegram", "lms: answering at 9600 baud",
                           "lms: 180 deg at 0.50 deg, streaming at 500000 baud"})
    EXPECT_NE(console.find(said), std::string::npos) << said << "\n" << console;
  EXPECT_EQ(console.find("lms: no answer"), std::string::npos) << console;
  // The MPU-6000's data-ready (1 kHz: SMPLRT_DIV 0 with DLPF_CFG 3) heard on A9 from the first
  // take_imu, after the 100 ms gyro start-up and mpu_begin, to the line: the line's time less
  // about 0.12 s, in samples, give or take 5 % for where exactly the first take fell.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(console, m, std::regex("(\\d+\\.\\d+) imu: (\\d+) samples standing"))) << console;
  const double imu_expected = 1000.0 * (std::stod(m[1].str()) - 0.12);
  EXPECT_NEAR(std::stod(m[2].str()), imu_expected, 0.05 * imu_expected) << console;

  // What reached USART1 from 2.2 s (streaming) to the end: whole scans, each 361 values (180
  // degrees at 0.5), at the LMS200's 37.5 a second (two interlaced 75 Hz sweeps make one 0.5
  // degree scan), 48.75 in 1.3 s, one either way for where the window cuts.
  const auto rx = uart_bytes(read_file(out / "rover.main.uart1.log"), "rx");
  std::vector<int> stream;
  for (const auto& b : rx)
    if (b.first >= 2200000000) stream.push_back(b.second);
  int scans = 0;
  std::vector<int> nearest_ahead;  // per scan: the nearest value 60 degrees either side of ahead, mm
  for (std::size_t i = 0; i + 7 < stream.size();) {
    const std::size_t length = static_cast<std::size_t>(stream[i + 2] | stream[i + 3] << 8);
    if (stream[i] != 0x02 || stream[i + 1] != 0x80 || stream[i + 4] != 0xB0 || i + length + 6 > stream.size() ||
        sick_crc(stream, i, length + 4) != (stream[i + length + 4] | stream[i + length + 5] << 8)) {
      ++i;
      continue;
    }
    const int count_word = stream[i + 5] | stream[i + 6] << 8;
    EXPECT_EQ(count_word & 0x3FF, 361);
    EXPECT_EQ(length, 1u + 2u + 2u * 361u + 1u);
    const int mm_per_unit = (count_word >> 14) == 0 ? 10 : 1;  // bits 14-15: 00 cm, 01 mm
    int nearest = 8183 * 10;
    for (int k = 120; k <= 240; ++k) {
      const int v = (stream[i + 7 + 2 * k] | stream[i + 8 + 2 * k] << 8) & 0x1FFF;
      if (v > 0 && v < 8183) nearest = std::min(nearest, v * mm_per_unit);  // 8183 up: no return
    }
    nearest_ahead.push_back(nearest);
    ++scans;
    i += length + 6;
  }
  EXPECT_NEAR(scans, 48.75, 1.0);
  // The rover's report after 3 s says how near the nearest return ahead is in the scans it looked
  // at (one in four, printed to the cm below): within the range of the scans it had.
  ASSERT_TRUE(std::regex_search(console, m, std::regex("3\\.\\d+ wp 1/4 .*lidar ahead (\\d+)\\.(\\d\\d) m")))
      << console;
  ASSERT_FALSE(nearest_ahead.empty());
  const int seen_mm = std::stoi(m[1].str()) * 1000 + std::stoi(m[2].str()) * 10;
  EXPECT_GE(seen_mm, *std::min_element(nearest_ahead.begin(), nearest_ahead.end()) - 10) << console;
  EXPECT_LE(seen_mm, *std::max_element(nearest_ahead.begin(), nearest_ahead.end())) << console;
}

// Every occurrence of `from` in `text` replaced by `to`.
std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

// The reference rover's own scenario (firmware_examples/rover/scenario_default.xml: bring-up by
// 4 s, waypoint 1 by 24 s, round the obstacles towards waypoint 2 by 36 s, no collision) met by
// its AVR build: the default project with engine="avr", its relative paths made absolute.
TEST(AvrEngine, TheReferenceRoversAvrBuildMeetsItsScenario) {
  TempDir dir;
  const std::string assets = SEAR_ASSET_DIR;
  std::string project = read_file(assets + "/projects/default.xml");
  const std::string mcu = "<mcu name=\"main\" clock_hz=\"16e6\">";
  ASSERT_NE(project.find(mcu), std::string::npos);
  project = replace_all(project, mcu, "<mcu name=\"main\" engine=\"avr\" clock_hz=\"16e6\">");
  project = replace_all(replace_all(project, "\"../../", "\"" + assets + "/../"), " ../../", " " + assets + "/../");
  project = replace_all(project, "\"../", "\"" + assets + "/");
  dir.write("project/default_avr.xml", project);
  std::string scenario = read_file(assets + "/../firmware_examples/rover/scenario_default.xml");
  const std::string original = "project=\"../../assets/projects/default.xml\"";
  ASSERT_NE(scenario.find(original), std::string::npos);
  dir.write("scenario/rover_avr.xml", replace_all(scenario, original, "project=\"../project/default_avr.xml\""));
  const std::string cmd = std::string(SEAR_BINARY) + " test " + (dir.path() / "scenario").string() + " -o " +
                          (dir.path() / "out").string() + " >" + (dir.path() / "log").string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  const std::string log = read_file(dir.path() / "log");
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << log;
  EXPECT_NE(log.find("PASS  rover_avr.xml seed 1: 11 expectations met"), std::string::npos) << log;
  // Its image sets up the SPI bus (MOSI 51, SCK 52 made outputs) for the IMU wired by its chip
  // select: those pins drive a device, so no note calls them wired to nothing.
  const auto summary = nlohmann::json::parse(read_file(dir.path() / "out" / "rover_avr.xml" / "seed-1" / "summary.json"));
  EXPECT_TRUE(summary["wiring"].empty()) << summary["wiring"].dump(2);
}

// `sear run --cross-check`: the avoider's first 3 s on both engines say and send the same and end
// within the stated bound of each other (its decisions differ in time by the HAL's cost model
// against real cycles, about a millisecond, which moves the rover well under a centimetre).
TEST(AvrEngine, CrossCheckOfTheAvoiderFindsTheEnginesAgree) {
  TempDir dir;
  const auto out = dir.path() / "out";
  const std::string cmd = std::string(SEAR_BINARY) + " run " SEAR_ASSET_DIR "/projects/avoider_hills.xml --cross-check " +
                          "--quiet --duration 3 -o " + out.string() + " 2>" + (dir.path() / "err").string();
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << read_file(dir.path() / "err");
  const auto report = nlohmann::json::parse(read_file(out / "cross_check.json"));
  EXPECT_EQ(WEXITSTATUS(status), 0) << report.dump(2);
  EXPECT_TRUE(report["differences"].empty()) << report.dump(2);
  EXPECT_LT(report["robots"]["rover"]["final_distance_m"].get<double>(), report["pose_bound_m"].get<double>());
  const auto& console = report["consoles"]["rover.main.console.log"];
  EXPECT_GE(console["lines_alike"].get<int>(), 1);  // "avoider: ready" at least
  EXPECT_EQ(console["lines_alike"], console["lines_native"]);
  EXPECT_TRUE(std::filesystem::exists(out / "native" / "summary.json"));
  EXPECT_TRUE(std::filesystem::exists(out / "avr" / "rover.main.avr.json"));
}

// A project's build flags (issue 21): a firmware that needs a define, a header from an include
// folder, C11 and a C++ source builds and runs on both engines with the flags its <firmware>
// gives, and without the define fails to build at its #error.
std::string flags_mcu(const std::string& engine, const std::string& defines) {
  const std::string dir = test_firmware("flags");
  return "    <mcu name=\"main\" engine=\"" + engine + "\">\n      <firmware sources=\"" + dir + "/main.c " + dir +
         "/twice.cpp\" includes=\"" + dir + "/include\" " + defines + " c_std=\"c11\" cxx_std=\"c++14\"/>\n    </mcu>\n";
}

class BuildFlags : public ::testing::TestWithParam<const char*> {};

TEST_P(BuildFlags, ReachTheCompilerForCAndCppSources) {
  TempDir dir;
  const auto run = run_sear(dir, rover_project(flags_mcu(GetParam(), "defines=\"REPEAT=2 UNUSED\""), "", 0.05));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string console = run.file("rover.main.console.log");
  EXPECT_NE(console.find("flags: hello 0 twice 0"), std::string::npos) << console;
  EXPECT_NE(console.find("flags: hello 1 twice 2"), std::string::npos) << console;
  EXPECT_EQ(console.find("flags: hello 2"), std::string::npos) << console;  // REPEAT=2: two lines
}

TEST_P(BuildFlags, AMissingDefineFailsTheBuildAtItsLine) {
  TempDir dir;
  const auto run = run_sear(dir, rover_project(flags_mcu(GetParam(), ""), "", 0.05));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("main.c:10:"), std::string::npos) << run.err;  // the #error line
  EXPECT_NE(run.err.find("REPEAT must come from the project"), std::string::npos) << run.err;
}

INSTANTIATE_TEST_SUITE_P(Engines, BuildFlags, ::testing::Values("native", "avr"));

// An endless empty loop halts the chip but not the run: `for (;;) {}` after sei() is halted with
// its interrupts on, and main() returning ends in avr-libc's exit(), `cli` then `rjmp .-2`: halted
// with interrupts off. Either is reported once, the run exits 0.
struct Halting {
  const char* source;
  const char* interrupts;
  int cycles;  // from the SBI that sets pin 13 to the first jump of the loop
};

class AvrHalt : public ::testing::TestWithParam<Halting> {};

TEST_P(AvrHalt, IsReportedWhenTheLoopBeginsAndTheRunGoesOn) {
  TempDir dir;
  dir.write("halting.c", GetParam().source);
  const auto run = run_sear(dir, rover_project(avr_mcu((dir.path() / "halting.c").string()), "", 0.02));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_EQ(summary["status"], "completed");
  ASSERT_EQ(summary["mcu_halts"].size(), 1u) << summary.dump();
  EXPECT_EQ(summary["mcu_halts"][0]["interrupts"], GetParam().interrupts);
  // Pin 13 (PB7) goes HIGH with an SBI, its edge stamped at the instruction's first cycle; the
  // loop's first RJMP begins once the instructions between have run, at their cycle counts in the
  // AVR instruction set manual. Both times are rounded down to the nanosecond.
  const auto t = edges(run, 13);
  ASSERT_EQ(t.size(), 2u);  // out LOW, then HIGH
  const double halted_ns = summary["mcu_halts"][0]["sim_time_s"].get<double>() * 1e9;
  EXPECT_NEAR(halted_ns, static_cast<double>(t[1]) + GetParam().cycles * kCycleNs, 1.0);
}

INSTANTIATE_TEST_SUITE_P(
    Images, AvrHalt,
    ::testing::Values(Halting{"#include <avr/interrupt.h>\n#include <avr/io.h>\n"
                              "int main(void) { DDRB |= _BV(PB7); PORTB |= _BV(PB7); sei(); for (;;) {} }\n",
                              "on", 2 + 1},  // SBI, SEI
                      Halting{"#include <avr/io.h>\n"
                              "int main(void) { DDRB |= _BV(PB7); PORTB |= _BV(PB7); return 0; }\n",
                              // SBI, two LDI (return 0), RET (5 cycles with the 2560's 3-byte PC),
                              // crt's JMP to _exit, CLI
                              "off", 2 + 1 + 1 + 5 + 3 + 1},
                      // An IJMP to itself (Z set by two LDI), which a local run may not end with.
                      Halting{"#include <avr/io.h>\n"
                              "int main(void) { DDRB |= _BV(PB7); PORTB |= _BV(PB7);\n"
                              "  __asm__ volatile(\"ldi r30, lo8(pm(1f))\\n\\tldi r31, hi8(pm(1f))\\n\\tnop\\n1:\\tijmp\");\n"
                              "  return 0; }\n",
                              "off", 2 + 1 + 1 + 1}),  // SBI, two LDI, NOP
    case_name<Halting>);

// A firmware the chip cannot survive stops its MCU with a report saying what the chip did.
struct Hostile {
  const char* source;
  const char* says;
};

class AvrHostile : public ::testing::TestWithParam<Hostile> {};

TEST_P(AvrHostile, IsReportedAndStopsTheMcu) {
  TempDir dir;
  dir.write("hostile.c", GetParam().source);
  const auto run = run_sear(dir, rover_project(avr_mcu((dir.path() / "hostile.c").string()), "", 0.2));
  EXPECT_EQ(run.exit_code, 3) << run.err;
  EXPECT_NE(run.err.find(GetParam().says), std::string::npos) << run.err;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_EQ(summary["mcu_stops"][0]["mcu"], "rover.main");
}

INSTANTIATE_TEST_SUITE_P(
    Images, AvrHostile,
    ::testing::Values(
        Hostile{"#include <avr/interrupt.h>\n#include <avr/sleep.h>\n"
                "int main(void) { cli(); sleep_enable(); sleep_cpu(); return 0; }\n",
                "halted: sleep with interrupts off"},
        Hostile{"int main(void) { ((void (*)(void))0x7000)(); /* word address: byte 0xE000, far past this program */ return 0; }\n", "jumped into nowhere"},
        Hostile{"#include <stdint.h>\nvolatile uint8_t sink;\n"
                "static uint16_t deep(uint16_t n) { volatile uint8_t pad[32]; pad[0] = (uint8_t)n; sink = pad[0];\n"
                "  return (uint16_t)(deep((uint16_t)(n + 1)) + pad[0]); }\n"
                "int main(void) { return deep(0); }\n",
                "stack ran into .bss"},
        // The watchdog at its shortest (15 ms, datasheet table 12-2) and never reset.
        Hostile{"#include <avr/wdt.h>\nint main(void) { wdt_enable(WDTO_15MS); for (;;) {} }\n", "reset"},
        // A read past RAMEND (0x21FF) by an LD the engine already runs inside a local run (200
        // passes read a global first): reported as the chip's crash, with simavr's reason.
        Hostile{"#include <stdint.h>\nvolatile uint8_t sink, other;\nvolatile uint8_t *volatile p = &other;\n"
                "int main(void) { for (uint8_t i = 0;; ++i) { if (i == 200) p = (volatile uint8_t *)0x3000;\n"
                "  volatile uint8_t *q = p; sink = *q; sink = i; } }\n",
                "Address 3000 out of ram"}),
    case_name<Hostile>);

// Random bytes as flash: whatever they decode to, the run ends by itself, a chip that fails says
// how in the chip's terms (never as simavr's bare "avr_sadly_crashed"; image 9 reads past RAM),
// its events before the failure are taken (image 7's pin changes at cycle 13 once read as a
// corrupted link), and no engine is left.
TEST(AvrEngine, RandomBytesAsFlashAreReportedAndLeaveNothingRunning) {
  int stopped = 0;
  for (unsigned seed = 1; seed <= 12; ++seed) {
    TempDir dir;
    std::mt19937 random(seed);  // fixed seeds: the same images every run
    std::string bytes(4096, '\0');
    for (auto& b : bytes) b = static_cast<char>(random() & 0xff);
    dir.write("random.bin", bytes);
    const std::string objcopy = "cd " + dir.path().string() +
                                " && avr-objcopy -I binary -O elf32-avr -B avr:6 --rename-section "
                                ".data=.text,contents,alloc,load,readonly,code random.bin random.elf";
    ASSERT_EQ(std::system(objcopy.c_str()), 0) << objcopy;
    const std::string mcu = "    <mcu name=\"main\" engine=\"avr\">\n      <firmware elf=\"" +
                            (dir.path() / "random.elf").string() + "\"/>\n    </mcu>\n";
    const auto run = run_sear(dir, rover_project(mcu, "", 0.05));
    // 0: the bytes happened to make a program that runs to the end, as they may on the chip.
    ASSERT_TRUE(run.exit_code == 0 || run.exit_code == 3) << "seed " << seed << ": " << run.err;
    if (run.exit_code == 3) {
      ++stopped;
      EXPECT_TRUE(std::regex_search(run.err, std::regex("jumped into nowhere: pc 0x[0-3][0-9a-f]{4} |crashed at pc "
                                                        "0x[0-9a-f]{5}, cycle [0-9]+: [A-Z]|stack|reset|halted")))
          << "seed " << seed << ": " << run.err;
      EXPECT_EQ(run.err.find("avr_sadly_crashed"), std::string::npos) << "seed " << seed << ": " << run.err;
    }
    // The engine runs with the image's path on its command line. (The run's keeper, a fork of
    // `sear` that outlives it by design for a moment, is not the engine.)
    for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
      const std::string cmdline = read_file(entry.path() / "cmdline");
      EXPECT_EQ(cmdline.find((dir.path() / "random.elf").string()), std::string::npos)
          << "seed " << seed << ": left running: " << entry.path() << " " << cmdline;
    }
  }
  // Random code leaves a 4 KiB image, or reads a data address past RAM, within a few dozen
  // instructions nearly always (all of the first 40 of these images do, within 0.05 s).
  EXPECT_GE(stopped, 9);
}

}  // namespace
}  // namespace sear::test
