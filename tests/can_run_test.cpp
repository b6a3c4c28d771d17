// CAN between MCUs end to end: two firmwares on one <can_bus> queue frames at the same instant
// and the bus orders and times them as ISO 11898-1 arbitration and bit stuffing say; acceptance
// filters, the two receive buffers' overrun, a lone node's error counters, the candump log, and
// the same bytes on every run.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include "firmware_run.hpp"
#include "runtime/can_bits.hpp"

namespace sear::test {
namespace {

constexpr double kBitNs = 2000;  // 500 kbit/s, the probes' rate
// The probe reads micros() and queues the frame with the next HAL call: 50 cycles at 16 MHz later.
constexpr double kCallS = 50 / 16e6;

std::string mcu(const std::string& name, const char* firmware, const std::string& bus = "body") {
  return "    <mcu name=\"" + name + "\">\n      <firmware executable=\"" + firmware + "\"/>\n" +
         (bus.empty() ? "" : "      <can bus=\"" + bus + "\"/>\n") + "    </mcu>\n";
}

std::string can_project(const std::string& mcus, const std::string& bus = "<can_bus name=\"body\" bitrate=\"500000\"/>") {
  return "<project name=\"can\">\n  <run duration=\"0.3\" seed=\"1\" trace_rate=\"10\"/>\n" + bus +
         "\n  <world step=\"0.001\">\n    <terrain type=\"flat\"/>\n  </world>\n  <robot file=\"" SEAR_ASSET_DIR
         "/robots/rover.xml\">\n    <pose x=\"0\" y=\"0\"/>\n" +
         mcus + "  </robot>\n</project>\n";
}

struct LogLine {
  double time_s;
  std::string iface, frame;
};

std::vector<LogLine> candump(const SearRun& run, const std::string& bus) {
  std::vector<LogLine> out;
  for (const auto& line : lines_of(run.file(bus + ".candump.log"))) {
    char iface[32], frame[64];
    double t = 0;
    if (std::sscanf(line.c_str(), "(%lf) %31s %63s", &t, iface, frame) == 3) out.push_back({t, iface, frame});
  }
  return out;
}

// Console lines "rx <us> <id> <dlc> <data>" by identifier, and the counters line.
struct Console {
  std::map<std::string, std::vector<long>> rx_us;
  std::vector<long> tx_us;
  std::vector<int> tx_result;
  int tec = -1, rec = -1, state = -1, overruns = -1, pending = -1;
};

Console console(const SearRun& run, const std::string& mcu_id) {
  Console c;
  for (const auto& line : lines_of(run.file(mcu_id + ".console.log"))) {
    long us = 0;
    char id[16];
    int result = 0;
    if (std::sscanf(line.c_str(), "%*s rx %ld %15s", &us, id) == 2) c.rx_us[id].push_back(us);
    else if (std::sscanf(line.c_str(), "%*s tx %ld %15s %d", &us, id, &result) == 3) {
      c.tx_us.push_back(us);
      c.tx_result.push_back(result);
    } else
      std::sscanf(line.c_str(), "%*s counters %d %d %d %d %d", &c.tec, &c.rec, &c.state, &c.overruns, &c.pending);
  }
  return c;
}

CanFrame probe_frame(std::uint32_t id, std::uint8_t n) {
  CanFrame f;
  f.id = id;
  f.dlc = 8;
  f.data = {n, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77};
  return f;
}

TEST(CanRun, TwoMcusQueueingAtOnceAreOrderedByIdentifierAndTimedByTheirBits) {
  TempDir dir;
  const SearRun run = run_sear(dir, can_project(mcu("a", CAN_PROBE_200) + mcu("b", CAN_PROBE_100)));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  Console a = console(run, "rover.a"), b = console(run, "rover.b");
  // Same code before the send: both queue at the same instant.
  ASSERT_EQ(a.tx_us.size(), 1u);
  ASSERT_EQ(b.tx_us.size(), 1u);
  ASSERT_EQ(a.tx_us[0], b.tx_us[0]);
  const double queued_s = static_cast<double>(a.tx_us[0]) * 1e-6;

  const auto log = candump(run, "body");
  ASSERT_EQ(log.size(), 2u) << run.file("body.candump.log");
  EXPECT_EQ(log[0].iface, "body");
  // 0x100 wins arbitration (its ID's first differing bit is dominant), 0x200 follows after the
  // 3 bits of intermission.
  EXPECT_EQ(log[0].frame, "100#0011223344556677");
  EXPECT_EQ(log[1].frame, "200#0011223344556677");
  const int bits_100 = can_bits::wire_bits(probe_frame(0x100, 0));
  const int bits_200 = can_bits::wire_bits(probe_frame(0x200, 0));
  // A standard frame with 8 data bytes is 108 bits before stuffing, at most 132 with it.
  EXPECT_GE(bits_100, 108);
  EXPECT_LE(bits_100, 132);
  // The log and micros() both truncate to whole microseconds: 1 us covers both.
  EXPECT_NEAR(log[0].time_s - (queued_s + kCallS), bits_100 * kBitNs * 1e-9, 1e-6);
  EXPECT_NEAR(log[1].time_s - log[0].time_s, (can_bits::kIntermissionBits + bits_200) * kBitNs * 1e-9, 1e-6);

  // Each receives the other's frame exactly one quantum (1 ms) after it ended on the wire (the
  // bus is decided at quantum ends), at the probe's next look: it polls every 100 us.
  ASSERT_EQ(a.rx_us["100"].size(), 1u);
  ASSERT_EQ(b.rx_us["200"].size(), 1u);
  EXPECT_EQ(a.rx_us.count("200"), 0u);  // a controller does not receive its own frame
  for (const auto& [got_us, end_s] : {std::pair{a.rx_us["100"][0], log[0].time_s}, {b.rx_us["200"][0], log[1].time_s}}) {
    EXPECT_GE(static_cast<double>(got_us) * 1e-6, end_s + 1e-3 - 1e-6);  // 1 us: both truncate to microseconds
    EXPECT_LE(static_cast<double>(got_us) * 1e-6, end_s + 1e-3 + 120e-6);  // + one 100 us poll and its calls
  }
  // Both acked by the other: no errors counted, nothing left to send.
  EXPECT_EQ(a.tec, 0);
  EXPECT_EQ(a.pending, 0);
  EXPECT_EQ(b.pending, 0);

  // Same project and seed: the same bytes.
  TempDir again;
  const SearRun second = run_sear(again, can_project(mcu("a", CAN_PROBE_200) + mcu("b", CAN_PROBE_100)));
  EXPECT_EQ(second.file("body.candump.log"), run.file("body.candump.log"));
  EXPECT_EQ(second.file("rover.a.console.log"), run.file("rover.a.console.log"));
}

TEST(CanRun, ThreeTransmitBuffersTwoReceiveBuffersAndFilters) {
  TempDir dir;
  // "burst" queues five 0x100 frames at once and never reads; "slow" sends 0x300, keeps only
  // 0x100 and reads from 100 ms on; "picky" sends 0x180 and keeps only 0x300.
  const SearRun run = run_sear(dir, can_project(mcu("burst", CAN_PROBE_BURST) + mcu("slow", CAN_PROBE_SLOW) +
                                                mcu("picky", CAN_PROBE_PICKY)));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  Console burst = console(run, "rover.burst"), slow = console(run, "rover.slow"), picky = console(run, "rover.picky");
  // Three transmit buffers take the first three; the fourth and fifth find them all waiting.
  EXPECT_EQ(burst.tx_result, (std::vector<int>{0, 0, 0, -1, -1}));
  EXPECT_EQ(burst.pending, 0);
  // Two receive buffers: the third frame, arriving with both full, is lost and counted.
  EXPECT_EQ(slow.rx_us["100"].size(), 2u);
  EXPECT_EQ(slow.overruns, 1);
  EXPECT_EQ(slow.rx_us.count("180"), 0u);
  // slow's 0x300 reaches the node whose filter keeps it; picky's 0x180 is kept by nobody but
  // the node without filters, which reads nothing.
  EXPECT_EQ(picky.rx_us["300"].size(), 1u);
  EXPECT_EQ(picky.rx_us.count("100"), 0u);
  EXPECT_EQ(candump(run, "body").size(), 5u);  // 3 + 1 + 1 frames went over the bus
  EXPECT_EQ(picky.overruns, 0);
}

// SEAR's broadcast sends four frames back to back every 50 ms. They reach the controller with
// their spacing on the wire (each one quantum after its end), so a firmware looking every 100 us
// takes each in turn: only the very first burst, which lands while the probe sleeps through its
// first 10 ms, overflows the two receive buffers (four frames, two kept).
TEST(CanRun, FramesBackToBackArriveSpacedAsOnTheWire) {
  TempDir dir;
  const SearRun run =
      run_sear(dir, can_project(mcu("a", CAN_PROBE_100), "<can_bus name=\"body\" bitrate=\"500000\" broadcast_hz=\"20\"/>"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  Console a = console(run, "rover.a");
  EXPECT_EQ(a.overruns, 2);
  // Six bursts reach it in the 0.3 s run (0, 50, ..., 250 ms): every frame of each, but the first
  // burst's last two (0x720, 0x730), lost to the overrun.
  for (const char* id : {"700", "710"}) EXPECT_EQ(a.rx_us[id].size(), 6u) << id;
  for (const char* id : {"720", "730"}) EXPECT_EQ(a.rx_us[id].size(), 5u) << id;
  EXPECT_EQ(a.tec, 0);  // SEAR's node acknowledged the probe's own frame
}

TEST(CanRun, ALoneNodeIsNeverAcknowledgedAndStaysErrorPassive) {
  TempDir dir;
  const SearRun run = run_sear(dir, can_project(mcu("a", CAN_PROBE_100)));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  Console a = console(run, "rover.a");
  // ISO 11898-1: each ACK error adds 8 to TEC until error passive at 128, where ACK errors no
  // longer count; the frame stays queued, sent again and again.
  EXPECT_EQ(a.tec, 128);
  EXPECT_EQ(a.state, 1);
  EXPECT_EQ(a.pending, 1);
  // Nothing went over the bus: the log holds acknowledged frames only, as a listener records.
  EXPECT_TRUE(candump(run, "body").empty());
}

// The two-board example as a user runs it: every range frame the sensor board sends reaches the
// motor board, in order, within the time the bus and the lockstep allow.
TEST(CanRun, TheTwoBoardExampleCarriesEveryRangeFrame) {
  TempDir dir;
  const std::string cmd = std::string(SEAR_BINARY) + " run " + SEAR_EXAMPLES_DIR + "/can_nodes -q -d 3 -o " +
                          (dir.path() / "out").string() + " 2>" + (dir.path() / "err").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0) << read_file(dir.path() / "err");
  const SearRun run{0, "", "", dir.path() / "out"};
  std::map<int, double> sent, received;
  for (const auto& line : lines_of(run.file("rover.sensors.console.log"))) {
    double t = 0;
    int n = 0;
    if (std::sscanf(line.c_str(), "%lf tx 0x120 %*s %*s n=%d", &t, &n) == 2) sent[n] = t;
  }
  for (const auto& line : lines_of(run.file("rover.motors.console.log"))) {
    double t = 0;
    int n = 0;
    if (std::sscanf(line.c_str(), "%lf rx 0x120 %*s %*s n=%d", &t, &n) == 2) received[n] = t;
  }
  // One every 20 ms from 0.1 s: about 145 in 3 s.
  ASSERT_GT(sent.size(), 140u);
  for (const auto& [n, t] : sent) {
    if (t > 2.99) continue;  // sent in the last quantum: still on its way when the run ends
    ASSERT_TRUE(received.count(n)) << "frame n=" << n << " sent at " << t << " s never arrived";
    // Within 1.2 to 3 ms: the frame itself (~0.2 ms at 500 kbit/s) and the one quantum (1 ms)
    // the bus is decided after; then the difference of the two console lines' own transmission
    // (about 30 bytes at 115200 baud, 2.6 ms each), whose ends shift by the few bytes they differ
    // and by a line the motor board may still be sending: 0.5 ms either way is ample.
    EXPECT_GT(received[n], t + 0.7e-3);
    EXPECT_LT(received[n], t + 3e-3);
  }
  const std::string summary = run.file("summary.txt");
  EXPECT_NE(summary.find("collisions 0"), std::string::npos) << summary;
}

TEST(CanRun, ProjectErrorsNameTheBus) {
  TempDir dir;
  SearRun run = run_sear(dir, can_project(mcu("a", CAN_PROBE_100, "chassis")));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("mcu 'a' is on CAN bus 'chassis', but the project has no <can_bus name=\"chassis\">"),
            std::string::npos)
      << run.err;
  EXPECT_NE(run.err.find("project.xml:"), std::string::npos) << run.err;
  run = run_sear(dir, can_project(mcu("a", CAN_PROBE_100), "<can_bus name=\"body\" bitrate=\"300000\"/>"));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("'bitrate' 300000 is not a rate a CAN controller makes"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace sear::test
