// Firmware timing held to the HAL's cost model (docs/firmware.md, "Lockstep: what the firmware sees"): every
// HAL call acts at the moment it is made and then costs hal_call_cycles / clock_hz; delay_us and
// delay_ms last exactly what they ask, counted from the call, or the call's cost if that is
// longer; adc_read lasts its 104 us conversion. Checked to the nanosecond on the pin waveform
// (VCD, timescale 1 ns) at the default cost and at two others, across quantum ends. And the hang
// timeout held to its value: a firmware that stops calling the HAL is reported hung, after at
// least that much host time.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <regex>
#include <vector>

#include "model_run.hpp"

namespace sear::test {
namespace {

// The delays tests/firmware/timing_probe.c asks for, in its order.
const std::uint32_t kDelaysUs[] = {0, 1, 2, 3, 4, 7, 13, 100, 997, 1000, 1001, 2500, 12345};
constexpr std::int64_t kAdcConversionNs = 104000;  // 13 ADC clocks at 125 kHz (ATmega2560 datasheet 26.4)

// What the cost model says the probe does, with each HAL call costing `c` ns.
struct Expected {
  std::int64_t mode_ns;             // pin_mode(13, OUTPUT): the pin starts driving LOW
  std::vector<std::int64_t> edges;  // every toggle
  std::vector<std::uint32_t> stamps;
};

Expected model(std::int64_t c) {
  Expected e;
  std::int64_t t = c;  // hal_init() at 0
  e.mode_ns = t;
  t += c;
  const auto call = [&] {  // a call that acts at t and then costs c
    const std::int64_t at = t;
    t += c;
    return at;
  };
  const auto delay = [&](std::int64_t ns) {  // counted from the call; at least the call's cost
    t += std::max(ns, c);
  };
  for (const std::uint32_t d : kDelaysUs) {
    e.edges.push_back(call());
    e.stamps.push_back(static_cast<std::uint32_t>(call() / 1000));
    delay(static_cast<std::int64_t>(d) * 1000);
  }
  e.edges.push_back(call());
  delay(1'000'000);  // delay_ms(1)
  e.edges.push_back(call());
  delay(3'000'000);  // delay_ms(3)
  e.edges.push_back(call());
  delay(kAdcConversionNs);  // adc_read(0)
  e.edges.push_back(call());
  while (call() / 1000 < 50000) {  // while (micros() < 50000u) {}
  }
  e.edges.push_back(call());
  return e;
}

std::string timing_mcu(const std::string& name, const std::string& attributes) {
  return "    <mcu name=\"" + name + "\" " + attributes + ">\n      <firmware executable=\"" + TIMING_PROBE +
         "\"/>\n    </mcu>\n";
}

TEST(FirmwareTiming, DelaysCallsAndAdcReadsLastWhatTheCostModelSaysToTheNanosecond) {
  // Three copies of the probe, each on its own clock: the default 50 cycles at 16 MHz (3125 ns a
  // call), 30 cycles at 20 MHz (1500 ns) and 100 cycles at 8 MHz (12500 ns, longer than every
  // delay up to 7 us). The costs are whole nanoseconds, so no rounding enters the expectation.
  struct Clock {
    const char* name;
    std::string attributes;
    std::int64_t call_ns;
  };
  const Clock clocks[] = {{"a", "", 3125},
                          {"b", "clock_hz=\"20e6\" hal_call_cycles=\"30\"", 1500},
                          {"c", "clock_hz=\"8e6\" hal_call_cycles=\"100\"", 12500}};
  std::string mcus;
  for (const auto& c : clocks) mcus += timing_mcu(c.name, c.attributes);
  TempDir dir;
  const auto run = run_sear(dir, rover_project(mcus, "", 0.06));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const auto& c : clocks) {
    SCOPED_TRACE(std::string("mcu ") + c.name);
    const std::string id = std::string("rover.") + c.name;
    const std::string vcd = run.file(id + ".pins.vcd");
    // IEEE 1364 18.2.3.3: the header declares the unit every '#' time is counted in.
    EXPECT_NE(vcd.find("$timescale 1 ns $end"), std::string::npos) << vcd.substr(0, 300);
    const Expected e = model(c.call_ns);
    const auto changes = vcd_changes(vcd, vcd_id_of_pin(13));
    ASSERT_EQ(changes.size(), e.edges.size() + 2) << vcd;
    EXPECT_EQ(changes[0].time, 0);  // $dumpvars: an input, 'z'
    EXPECT_EQ(changes[0].value, 'z');
    EXPECT_EQ(changes[1].time, e.mode_ns);
    EXPECT_EQ(changes[1].value, '0');
    for (std::size_t k = 0; k < e.edges.size(); ++k) {
      EXPECT_EQ(changes[k + 2].time, e.edges[k]) << "edge " << k;
      EXPECT_EQ(changes[k + 2].value, k % 2 == 0 ? '1' : '0') << "edge " << k;
    }
    // micros() is the call's own time in whole microseconds.
    const std::string console = run.file(id + ".console.log");
    std::smatch m;
    for (std::size_t i = 0; i < e.stamps.size(); ++i) {
      const std::regex line(" stamp " + std::to_string(i) + " (\\d+)\n");
      ASSERT_TRUE(std::regex_search(console, m, line)) << console;
      EXPECT_EQ(std::stoul(m[1]), e.stamps[i]) << "stamp " << i;
    }
    EXPECT_NE(console.find(" adc 0\n"), std::string::npos) << console;  // nothing on channel 0: 0 V
    EXPECT_NE(console.find(" done\n"), std::string::npos) << console;
  }
}

TEST(FirmwareTiming, AFirmwareThatStopsCallingTheHalIsReportedHungAfterTheHangTimeout) {
  // The hang probe spins without HAL calls once delay_ms(300) has ended: 300 ms after it began,
  // which followed three calls of 3125 ns (hal_init, uart_begin, uart_print).
  TempDir dir;
  const double timeout_s = 1.5;  // not the default 5
  const auto start = std::chrono::steady_clock::now();
  const auto run = run_sear(dir, rover_project("    <mcu name=\"main\">\n      <firmware executable=\"" +
                                                   std::string(HANG_PROBE) + "\"/>\n    </mcu>\n"),
                            "--hang-timeout 1.5");
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(run.exit_code, 3) << run.err;
  EXPECT_NE(run.err.find("mcu rover.main hung: its clock stood still for 1.5 s of host time"), std::string::npos)
      << run.err;
  EXPECT_NE(run.err.find("at sim time 0.300009 s; last HAL call: delay_ms"), std::string::npos) << run.err;
  // Its clock stood still for the timeout, so the run took at least that long. The simulator
  // looks every 10 ms (mcu_process.cpp's kCheckNs) whether the clock moved, so on a quiet host the
  // hang is reported within the timeout plus 10 ms of the probe's last call, 0.3 simulated
  // seconds in (a few ms of host time). The bound leaves a loaded host another timeout and a
  // second for those: a hang reported at twice the timeout plus a second or later is late.
  EXPECT_GE(wall_s, timeout_s);
  const double latest_s = 2 * timeout_s + 1.0;
  const auto summary = nlohmann::json::parse(run.file("summary.json"));
  EXPECT_EQ(summary["status"], "mcu stopped");
  ASSERT_EQ(summary["mcu_stops"].size(), 1u);
  const auto& stop = summary["mcu_stops"][0];
  EXPECT_EQ(stop["mcu"], "rover.main");
  EXPECT_EQ(stop["kind"], "hung");
  EXPECT_EQ(stop["code"], 0);
  EXPECT_NE(stop["detail"].get<std::string>().find("its clock stood still for 1.5 s of host time"), std::string::npos)
      << stop.dump();
  EXPECT_DOUBLE_EQ(stop["sim_time_s"].get<double>(), 300009375e-9);
  EXPECT_EQ(stop["last_hal_call"], "delay_ms");
  EXPECT_GE(summary["wall_time_s"].get<double>(), timeout_s);
  EXPECT_LE(summary["wall_time_s"].get<double>(), latest_s);
}

}  // namespace
}  // namespace sear::test
