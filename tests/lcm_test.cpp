// `sear run --lcm` against LCM's own tools, inside a private network namespace so that no test
// traffic leaves this process tree: lcm-logger records a run, and the recording decodes with the
// generated types to what the run's trace says; an external controller drives a robot in lockstep;
// SEAR's own event log replays with lcm-logplayer; CONTROL pauses, steps and resets a run. The
// log alone (--lcm-log, no network) holds the MCU's OUTPUTS as a firmware with known timing sets them.
#include <gtest/gtest.h>
#include <lcm/eventlog.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "firmware_run.hpp"
#include "project_text.hpp"
#include "sear/lcm/sear/can_t.hpp"
#include "sear/lcm/sear/outputs_t.hpp"
#include "sear/lcm/sear/pose_t.hpp"
#include "sear/lcm/sear/reading_t.hpp"
#include "sear/lcm/sear/serial_t.hpp"
#include "sear/lcm/sear/sim_clock_t.hpp"

namespace sear::test {
namespace {

const std::string kUrl = "udpm://239.255.76.67:7667?ttl=0";
const std::string kRover = std::string(SEAR_ASSET_DIR) + "/robots/rover.xml";

// A private network namespace with multicast on its loopback: LCM's udpm default works in it and
// nothing reaches a real network. Tests run as root here and in CI.
bool namespace_works() {
  return std::system(
             "unshare -n sh -c 'ip link set lo up && ip link set lo multicast on && "
             "ip route add 239.0.0.0/8 dev lo' >/dev/null 2>&1") == 0 &&
         std::system("command -v lcm-logger >/dev/null && command -v lcm-logplayer >/dev/null") == 0;
}

#define REQUIRE_NAMESPACE()                                                                                      \
  do {                                                                                                           \
    if (!namespace_works()) {                                                                                    \
      if (std::getenv("CI"))                                                                                     \
        FAIL() << "cannot create a private network namespace (unshare -n, as root) or lcm-logger is missing";    \
      GTEST_SKIP() << "needs a private network namespace (unshare -n: run as root) and liblcm-bin's lcm-logger"; \
    }                                                                                                            \
  } while (0)

// Runs the shell `script` in a fresh namespace, in `dir`; SEAR, CONTROLLER and URL are set for it.
int in_namespace(const TempDir& dir, const std::string& script) {
  const std::string body = "set -u\ncd '" + dir.path().string() + "'\nSEAR='" + SEAR_BINARY + "'\nCONTROLLER='" +
                           LCM_CONTROLLER + "'\nURL='" + kUrl +
                           "'\nip link set lo up && ip link set lo multicast on && ip route add 239.0.0.0/8 dev lo "
                           "|| exit 90\n" +
                           script;
  const std::string file = dir.write("script.sh", body);
  const int status = std::system(("unshare -n sh '" + file + "'").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// RcvbufErrors from the two "Udp:" lines of /proc/net/snmp (names, then values).
std::uint64_t udp_receive_buffer_errors(const std::string& snmp) {
  std::istringstream in(snmp);
  std::string names, values;
  std::getline(in, names);
  std::getline(in, values);
  std::istringstream n(names), v(values);
  for (std::string name, value; n >> name && v >> value;)
    if (name == "RcvbufErrors") return std::stoull(value);
  ADD_FAILURE() << "no RcvbufErrors in " << snmp;
  return 0;
}

// Waits (up to 5 s) for a helper started with `&` to say it is subscribed.
const std::string kWaitReady = "for i in $(seq 100); do grep -q ready ctl.out 2>/dev/null && break; sleep 0.05; done\n";

struct Event {
  std::string channel;
  std::vector<std::uint8_t> data;
  std::int64_t timestamp;
};

std::vector<Event> read_log(const std::string& path) {
  std::vector<Event> events;
  lcm_eventlog_t* log = lcm_eventlog_create(path.c_str(), "r");
  if (!log) return events;
  while (lcm_eventlog_event_t* e = lcm_eventlog_read_next_event(log)) {
    // liblcm's udpm sends one message to itself when it starts, to check multicast works; the
    // pings tell that a logger listens.
    if (std::string(e->channel) == "LCM_SELF_TEST" || std::string(e->channel).rfind("TEST/", 0) == 0) {
      lcm_eventlog_free_event(e);
      continue;
    }
    const auto* d = static_cast<const std::uint8_t*>(e->data);
    events.push_back({std::string(e->channel, static_cast<std::size_t>(e->channellen)),
                      std::vector<std::uint8_t>(d, d + e->datalen), e->timestamp});
    lcm_eventlog_free_event(e);
  }
  lcm_eventlog_destroy(log);
  return events;
}

template <class T>
std::vector<T> decoded(const std::vector<Event>& events, const std::string& channel) {
  std::vector<T> out;
  for (const Event& e : events) {
    if (e.channel != channel) continue;
    T m;
    EXPECT_EQ(m.decode(e.data.data(), 0, static_cast<int>(e.data.size())), static_cast<int>(e.data.size())) << channel;
    out.push_back(m);
  }
  return out;
}

std::vector<std::vector<double>> csv_rows(const std::string& text) {
  std::vector<std::vector<double>> rows;
  const auto lines = lines_of(text);
  for (std::size_t i = 1; i < lines.size(); ++i) {
    std::vector<double> row;
    std::istringstream in(lines[i]);
    for (std::string cell; std::getline(in, cell, ',');) row.push_back(std::atof(cell.c_str()));
    rows.push_back(row);
  }
  return rows;
}

// A scripted rover (no MCU) driving an arc, and a second rover whose MCU reads a GP2D12 that
// faces a box 0.5 m ahead of it and carries a NEO-6M on UART 3.
std::string two_rovers(double duration_s) {
  std::ostringstream p;
  p << "<project name=\"lcm\">\n  <run duration=\"" << duration_s << "\" seed=\"1\" trace_rate=\"100\"/>\n"
    << "  <world step=\"0.001\">\n    <gps_origin latitude=\"52.2053\" longitude=\"0.1218\" altitude=\"12\"/>\n"
    << "    <terrain type=\"flat\"/>\n    <box name=\"target\" pos=\"0.75 3\" size=\"0.2 1 0.4\"/>\n  </world>\n"
    << "  <robot file=\"" << kRover << "\">\n    <pose x=\"0\" y=\"0\"/>\n    <script>\n"
    << "      <motor t=\"0.2\" name=\"left\" duty=\"0.6\" dir=\"forward\"/>\n"
    << "      <motor t=\"0.2\" name=\"right\" duty=\"0.4\" dir=\"forward\"/>\n    </script>\n  </robot>\n"
    << "  <robot name=\"probe\" file=\"" << kRover << "\">\n    <pose x=\"0\" y=\"3\"/>\n"
    << "    <mcu name=\"main\">\n      <firmware executable=\"" << IR_PROBE << "\"/>\n"
    << "      <gp2d12 name=\"ir\" adc=\"0\" pos=\"0.15 0 0.02\"/>\n"
    << "      <ublox_neo6m name=\"gps\" uart=\"3\"/>\n    </mcu>\n  </robot>\n</project>\n";
  return p.str();
}

// The rover alone, with no MCU, for an external controller; `script` adds scripted commands.
std::string lone_rover(double duration_s, const std::string& script = "") {
  std::ostringstream p;
  p << "<project name=\"lcm\">\n  <run duration=\"" << duration_s << "\" seed=\"1\" trace_rate=\"100\"/>\n"
    << "  <world step=\"0.001\">\n    <terrain type=\"flat\"/>\n  </world>\n"
    << "  <robot file=\"" << kRover << "\">\n    <pose x=\"0\" y=\"0\"/>\n"
    << script << "  </robot>\n</project>\n";
  return p.str();
}

// The recording decodes to the run: POSE matches the trace row of the same time to the trace's
// printed precision, CLOCK counts the steps, READING holds every sample of the ranger, TX the GPS's
// bytes at its baud rate; SEAR's own log holds exactly what the logger heard, and lcm-logplayer
// replays it event for event.
TEST(Lcm, LoggerRecordsWhatTheRunPublishesAndSearsLogReplays) {
  REQUIRE_NAMESPACE();
  TempDir dir;
  dir.write("project.xml", two_rovers(1.5));
  // A logger is listening once it has recorded one of the helper's pings. UDP drops what a
  // receiver's socket buffer cannot hold: on a machine busy with builds the logger may not run for
  // a while, so the run is paced at twice real time (a few messages per 10 ms) to keep it lossless.
  const std::string logger =
      "logger() { lcm-logger -q -f --flush-interval=10 --lcm-url=\"$URL\" $1 & logger=$!\n"
      "  for i in $(seq 200); do \"$CONTROLLER\" ping \"$URL\" TEST/PING; grep -q TEST/PING $1 2>/dev/null && return\n"
      "  sleep 0.025; done; kill $logger; exit 91; }\n"
      // ... and has written all that came before once it wrote a ping sent after the run.
      "logger_end() { for i in $(seq 200); do \"$CONTROLLER\" ping \"$URL\" TEST/END; grep -q TEST/END $1 && break\n"
      "  sleep 0.025; done; kill -INT $logger; wait $logger; }\n";
  // The namespace's UDP counters before and after: a datagram a full socket buffer dropped is
  // counted there (RcvbufErrors), and only such a loss may make a recording shorter than the log.
  ASSERT_EQ(in_namespace(dir, logger + "grep ^Udp: /proc/net/snmp >udp.before\nlogger live.lcmlog\n"
                                       "\"$SEAR\" run project.xml -q -o out --lcm --lcm-log out/sear.lcmlog "
                                       "--lcm-rate 100 --realtime 2 >stdout 2>stderr\n"
                                       "echo $? >sear.rc\nlogger_end live.lcmlog\n"
                                       "logger replay.lcmlog\nlcm-logplayer --lcm-url=\"$URL\" out/sear.lcmlog\n"
                                       "logger_end replay.lcmlog\ngrep ^Udp: /proc/net/snmp >udp.after\n"),
            0);
  ASSERT_EQ(read_file(dir.path() / "sear.rc"), "0\n") << read_file(dir.path() / "stderr");
  const auto live = read_log((dir.path() / "live.lcmlog").string());
  const auto own = read_log((dir.path() / "out/sear.lcmlog").string());
  const auto replay = read_log((dir.path() / "replay.lcmlog").string());
  ASSERT_GT(own.size(), 300u);

  // Every message went out over UDP and was heard, in order, but for those the kernel counted as
  // dropped (a message lost takes at least one datagram with it); the log holds the same bytes,
  // but for CLOCK's real-time factor, which is the host's speed: live only, 0 in the log.
  const auto same = [](const Event& heard, const Event& logged) {
    if (heard.channel != "SEAR/CLOCK") return heard.data == logged.data;
    sear::sim_clock_t h, l;
    if (h.decode(heard.data.data(), 0, static_cast<int>(heard.data.size())) < 0 ||
        l.decode(logged.data.data(), 0, static_cast<int>(logged.data.size())) < 0)
      return false;
    const bool rest = h.time_ns == l.time_ns && h.step == l.step && h.paused == l.paused &&
                      h.awaiting_drive == l.awaiting_drive && h.lockstep_every == l.lockstep_every;
    return rest && l.real_time_factor == 0;
  };
  const std::uint64_t dropped = udp_receive_buffer_errors(read_file(dir.path() / "udp.after")) -
                                 udp_receive_buffer_errors(read_file(dir.path() / "udp.before"));
  std::size_t missing = 0;
  for (const auto* heard : {&live, &replay}) {
    // Each message heard is the next one of the log that it matches: heard in order, none made up.
    std::size_t next = 0;
    for (std::size_t i = 0; i < heard->size(); ++i) {
      while (next < own.size() && !((*heard)[i].channel == own[next].channel && same((*heard)[i], own[next]))) ++next;
      ASSERT_LT(next, own.size()) << (heard == &live ? "live" : "replay") << " message " << i << " "
                                  << (*heard)[i].channel << " is not in the log, or out of order";
      ++next;
    }
    missing += own.size() - heard->size();
  }
  EXPECT_LE(missing, dropped) << "messages lost that no full socket buffer explains";

  // POSE: the trace prints %.6f, so both agree to half a unit of its last digit.
  const auto poses = decoded<sear::pose_t>(own, "SEAR/rover/POSE");
  std::map<std::int64_t, const sear::pose_t*> pose_at;
  for (const auto& p : poses) pose_at[p.time_ns] = &p;
  const auto rows = csv_rows(read_file(dir.path() / "out/trace_rover.csv"));
  ASSERT_EQ(rows.size(), 151u);  // 0 to 1.5 s at 100 Hz
  EXPECT_EQ(poses.size(), rows.size());
  double farthest = 0;
  for (const auto& row : rows) {
    const auto t = std::llround(row[0] * 1e9);
    ASSERT_TRUE(pose_at.count(t)) << "no POSE at " << row[0];
    const sear::pose_t& p = *pose_at[t];
    const double got[13] = {p.position[0],       p.position[1],         p.position[2],         p.roll_pitch_yaw[0],
                            p.roll_pitch_yaw[1], p.roll_pitch_yaw[2],   p.velocity[0],         p.velocity[1],
                            p.velocity[2],       p.angular_velocity[0], p.angular_velocity[1], p.angular_velocity[2],
                            p.forward_speed};
    for (int c = 0; c < 13; ++c)
      EXPECT_NEAR(got[c], row[1 + c], 5e-7 + 1e-12) << "column " << 1 + c << " at " << row[0];
    EXPECT_EQ(p.utime, t / 1000);
    // The quaternion is the Z-Y-X Euler angles' rotation: its yaw is the yaw (1e-9: rounding).
    const double w = p.orientation[0], x = p.orientation[1], y = p.orientation[2], z = p.orientation[3];
    EXPECT_NEAR(w * w + x * x + y * y + z * z, 1.0, 1e-9);
    EXPECT_NEAR(std::atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)), p.roll_pitch_yaw[2], 1e-9);
    farthest = std::max(farthest, std::hypot(p.position[0], p.position[1]));
  }
  EXPECT_GT(farthest, 0.2);  // it did drive: duties 0.6 and 0.4 for 1.3 s

  // CLOCK: every 10th step (100 Hz of 1 ms steps), none missing, none twice.
  const auto clocks = decoded<sear::sim_clock_t>(own, "SEAR/CLOCK");
  ASSERT_EQ(clocks.size(), 151u);
  for (std::size_t i = 0; i < clocks.size(); ++i) {
    EXPECT_EQ(clocks[i].step, static_cast<std::int64_t>(10 * i));
    EXPECT_EQ(clocks[i].time_ns, clocks[i].step * 1000000);
    EXPECT_EQ(clocks[i].step_ns, 1000000);
    EXPECT_FALSE(clocks[i].paused);
  }

  // READING: the GP2D12's ray, from 0.15 m ahead of the probe's chassis origin, ends on the box's
  // face at x = 0.65 m: 0.50 m at the start. The probe creeps (its motors coast) and pitches by a
  // few mrad; its own POSE says where the sensor (0.15 m ahead, 0.02 m up) is. Tolerance 20 um:
  // the POSE is of the start of the 10 ms period of the sample, and the probe creeps < 1 mm/s
  // (10 um); the ray's slant at 3 mrad lengthens 0.5 m by 2 um.
  const auto readings = decoded<sear::reading_t>(own, "SEAR/probe/main/ir/READING");
  std::map<std::int64_t, sear::pose_t> probe_at;
  for (const auto& p : decoded<sear::pose_t>(own, "SEAR/probe/POSE")) probe_at[p.time_ns] = p;
  ASSERT_FALSE(readings.empty());
  std::int64_t next_index = readings[0].sample_index.at(0), last_time = -1;
  std::size_t samples = 0;
  for (const auto& r : readings) {
    EXPECT_EQ(r.kind, "gp2d12");
    ASSERT_EQ(r.value_count, 1);
    EXPECT_EQ(r.quantity[0], "distance");
    EXPECT_EQ(r.unit[0], "m");
    for (int i = 0; i < r.sample_count; ++i, ++samples) {
      EXPECT_EQ(r.sample_index[i], next_index++) << "a sample lost between batches";
      EXPECT_GT(r.sample_time_ns[i], last_time);
      EXPECT_LE(r.sample_time_ns[i], r.time_ns);
      last_time = r.sample_time_ns[i];
      const sear::pose_t& p = probe_at.at(r.sample_time_ns[i] / 10000000 * 10000000);
      const double pitch = p.roll_pitch_yaw[1],
                   sensor_x = p.position[0] + 0.15 * std::cos(pitch) + 0.02 * std::sin(pitch);
      EXPECT_NEAR(r.value[i][0], 0.65 - sensor_x, 2e-5) << "at " << r.sample_time_ns[i];
    }
  }
  EXPECT_GT(samples, 10u);

  // TX: the NEO-6M's NMEA at 9600 baud; back-to-back bytes are one 8N1 frame, 10 bits, apart.
  const auto tx = decoded<sear::serial_t>(own, "SEAR/probe/main/gps/TX");
  std::string text;
  std::int64_t previous = -1, min_gap = INT64_MAX;
  for (const auto& m : tx) {
    EXPECT_TRUE(m.from_device);
    for (int i = 0; i < m.count; ++i) {
      EXPECT_EQ(m.baud[i], 9600);
      if (previous >= 0) min_gap = std::min(min_gap, m.end_ns[i] - previous);
      previous = m.end_ns[i];
      text += static_cast<char>(m.data[i]);
    }
  }
  EXPECT_NE(text.find("$GPRMC"), std::string::npos) << text;
  EXPECT_EQ(min_gap, (10'000'000'000 + 4800) / 9600);  // 1041667 ns, rounded as serial_frame_ns
}

// The controller answers every 10th step with duties 0.5/0.5; the run never takes a step it was
// not answered for, and the rover drives as the motor model says it must.
TEST(Lcm, ExternalControllerInLockstepSeesEveryStepAndDrivesTheRover) {
  REQUIRE_NAMESPACE();
  TempDir dir;
  dir.write("project.xml", lone_rover(1.5));
  ASSERT_EQ(in_namespace(dir, "\"$CONTROLLER\" drive \"$URL\" rover 0.5 0.5 -1 >ctl.out & ctl=$!\n" + kWaitReady +
                                  "\"$SEAR\" run project.xml -q -o out --lcm --lcm-lockstep 10 >stdout 2>stderr\n"
                                  "echo $? >sear.rc\nkill $ctl; wait $ctl 2>/dev/null || :\n"),
            0);
  ASSERT_EQ(read_file(dir.path() / "sear.rc"), "0\n") << read_file(dir.path() / "stderr");
  std::vector<long long> steps;
  for (const auto& line : lines_of(read_file(dir.path() / "ctl.out"))) {
    long long step = 0, t = 0;
    if (std::sscanf(line.c_str(), "clock %lld %lld", &step, &t) == 2) {
      steps.push_back(step);
      EXPECT_EQ(t, step * 1000000);
    }
    EXPECT_EQ(line.rfind("repeat", 0), std::string::npos) << line;
  }
  // Steps 0, 10, ..., 1490 each once: the 1500th step ends the run without a wait.
  ASSERT_EQ(steps.size(), 150u);
  for (std::size_t i = 0; i < steps.size(); ++i) EXPECT_EQ(steps[i], static_cast<long long>(10 * i));

  // Steady speed of a wheel on the motor's line T = duty * Ts - (Ts / w0) * w against its
  // gearbox's Coulomb friction Tf (rover.xml: Ts 0.6 N*m, w0 160 rpm, Tf 0.02 N*m, r 45 mm):
  // w = w0 * (duty - Tf / Ts), v = r * w = 0.3519 m/s. The chassis reaches it with a time
  // constant m r^2 w0 / (2 Ts) = 0.05 s, so from 1 s on it has; the caster's and the tyres'
  // rolling losses and the contacts' slip are not in the formula: 0.5 % covers them (0.03 % seen).
  const double w0 = 160 * 2 * 3.14159265358979323846 / 60, expected = 0.045 * w0 * (0.5 - 0.02 / 0.6);
  double sum = 0;
  int n = 0;
  for (const auto& row : csv_rows(read_file(dir.path() / "out/trace_rover.csv")))
    if (row[0] >= 1.0) {
      sum += row[13];
      ++n;
      EXPECT_NEAR(row[12], 0, 1e-3) << "equal duties drive straight, at " << row[0];
    }
  ASSERT_GT(n, 40);
  EXPECT_NEAR(sum / n, expected, 0.005 * expected);
}

// A controller that stops answering at step 200 ends the run after --lcm-timeout, with exit code 6
// and a message that names the robot and the step; the world never moved past that step.
TEST(Lcm, ControllerThatGoesSilentEndsTheRunWithItsExitCode) {
  REQUIRE_NAMESPACE();
  TempDir dir;
  dir.write("project.xml", lone_rover(1.5));
  ASSERT_EQ(in_namespace(dir, "\"$CONTROLLER\" drive \"$URL\" rover 0.5 0.5 200 >ctl.out & ctl=$!\n" + kWaitReady +
                                  "\"$SEAR\" run project.xml -q -o out --lcm --lcm-lockstep 10 --lcm-timeout 0.5 "
                                  ">stdout 2>stderr\necho $? >sear.rc\nkill $ctl; wait $ctl 2>/dev/null || :\n"),
            0);
  EXPECT_EQ(read_file(dir.path() / "sear.rc"), "6\n");
  EXPECT_NE(read_file(dir.path() / "stderr")
                .find("sear: no DRIVE for robot 'rover' answering step 200 within 0.5 s: the controller is gone"),
            std::string::npos)
      << read_file(dir.path() / "stderr");
  const auto rows = csv_rows(read_file(dir.path() / "out/trace_rover.csv"));
  ASSERT_FALSE(rows.empty());
  EXPECT_NEAR(rows.back()[0], 0.2, 1e-9);
  EXPECT_NE(read_file(dir.path() / "out/summary.json").find("lcm controller gone"), std::string::npos);
}

// PAUSE holds the clock, STEP 25 advances exactly 25 steps, RESET starts over at t = 0 (still
// paused), RESUME runs to the end; the trace then is the same, byte for byte, as a run left alone.
TEST(Lcm, ControlPausesStepsAndResetsTheRun) {
  REQUIRE_NAMESPACE();
  TempDir dir;
  const std::string script =
      "    <script>\n      <motor t=\"0.1\" name=\"left\" duty=\"0.7\" dir=\"forward\"/>\n"
      "      <motor t=\"0.1\" name=\"right\" duty=\"0.3\" dir=\"forward\"/>\n    </script>\n";
  dir.write("project.xml", lone_rover(2, script));
  // --realtime 4: slow enough that the controller's PAUSE arrives long before the run's end.
  ASSERT_EQ(in_namespace(dir, "\"$CONTROLLER\" control \"$URL\" 2000 >ctl.out & ctl=$!\n" + kWaitReady +
                                  "\"$SEAR\" run project.xml -q -o out --lcm --realtime 4 >stdout 2>stderr\n"
                                  "echo $? >sear.rc\nwait $ctl; echo $? >ctl.rc\n"
                                  "\"$SEAR\" run project.xml -q -o plain >/dev/null 2>&1\n"),
            0);
  ASSERT_EQ(read_file(dir.path() / "sear.rc"), "0\n") << read_file(dir.path() / "stderr");
  ASSERT_EQ(read_file(dir.path() / "ctl.rc"), "0\n") << read_file(dir.path() / "ctl.out");
  long long paused = -1, held = -1, stepped = -1, reset_step = -1, reset_t = -1, ended = -1;
  int reset_paused = -1;
  for (const auto& line : lines_of(read_file(dir.path() / "ctl.out"))) {
    std::sscanf(line.c_str(), "paused %lld", &paused);
    std::sscanf(line.c_str(), "held %lld", &held);
    std::sscanf(line.c_str(), "stepped %lld", &stepped);
    std::sscanf(line.c_str(), "reset %lld %lld paused %d", &reset_step, &reset_t, &reset_paused);
    std::sscanf(line.c_str(), "ended %lld", &ended);
  }
  EXPECT_GE(paused, 200);
  EXPECT_EQ(held, paused);
  EXPECT_EQ(stepped, paused + 25);
  EXPECT_EQ(reset_step, 0);
  EXPECT_EQ(reset_t, 0);
  EXPECT_EQ(reset_paused, 1);
  EXPECT_EQ(ended, 2000);
  EXPECT_NE(read_file(dir.path() / "stderr").find("reset by SEAR/CONTROL"), std::string::npos);
  const std::string trace = read_file(dir.path() / "out/trace_rover.csv");
  EXPECT_EQ(lines_of(trace).size(), 202u);  // header and 0..2 s at 100 Hz
  EXPECT_EQ(trace, read_file(dir.path() / "plain/trace_rover.csv"));
}

// Without --lcm the log alone is written, with the same messages; each event is stamped with its
// sim time in microseconds, so that lcm-logplayer replays at the simulated pace.
TEST(Lcm, LogWithoutLcmHoldsTheMessagesStampedWithSimTime) {
  TempDir dir;
  const SearRun run = run_sear(dir, lone_rover(0.3), "-q --lcm-log " + (dir.path() / "run.lcmlog").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto events = read_log((dir.path() / "run.lcmlog").string());
  const auto clocks = decoded<sear::sim_clock_t>(events, "SEAR/CLOCK");
  ASSERT_EQ(clocks.size(), 16u);  // 0 to 0.3 s at the default 50 Hz
  const auto poses = decoded<sear::pose_t>(events, "SEAR/rover/POSE");
  ASSERT_EQ(poses.size(), 16u);
  std::int64_t last = -1;
  for (const Event& e : events) {
    EXPECT_GE(e.timestamp, last);
    last = e.timestamp;
  }
  EXPECT_EQ(last, 300000);
  EXPECT_EQ(decoded<sear::outputs_t>(events, "SEAR/rover/main/OUTPUTS").size(), 0u);  // no MCU, no outputs
  // Same project, same seed: the same log, byte for byte.
  TempDir again;
  ASSERT_EQ(run_sear(again, lone_rover(0.3), "-q --lcm-log " + (again.path() / "run.lcmlog").string()).exit_code, 0);
  EXPECT_EQ(read_file(again.path() / "run.lcmlog"), read_file(dir.path() / "run.lcmlog"));
}

// OUTPUTS follow the waveform probe's pins (every HAL call free, so each change falls at a delay's
// end): one message at the end of each 1 ms step in which something changed, none otherwise, and
// the pin it sets to INPUT leaves the list.
TEST(Lcm, OutputsSayWhatThePinsDriveAfterEachStepThatChangedThem) {
  TempDir dir;
  const std::string mcu = std::string("    <mcu name=\"main\" hal_call_cycles=\"0\">\n      <firmware executable=\"") +
                          WAVEFORM_PROBE + "\"/>\n      <uart port=\"1\" loopback=\"true\"/>\n    </mcu>\n";
  const SearRun run =
      run_sear(dir, rover_project(mcu, "", 0.1), "-q --lcm-log " + (dir.path() / "run.lcmlog").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto outputs =
      decoded<sear::outputs_t>(read_log((dir.path() / "run.lcmlog").string()), "SEAR/rover/main/OUTPUTS");
  // Changes at 0 and 1.5 ms (pin 4 an output, LOW, then HIGH) and at 5, 15, 25, 35, 45 and 55 ms,
  // each seen at the end of its step. Duty = value / 255; pwm_write(0) is a plain low level and
  // digital_write(HIGH) ends the PWM; servo pulses in s.
  struct Pin {
    int pin, drive;
    double value;
  };
  const Pin four{4, sear::outputs_t::LEVEL, 1};
  const std::vector<std::pair<std::int64_t, std::vector<Pin>>> expected = {
      {1000000, {{4, sear::outputs_t::LEVEL, 0}}},
      {2000000, {four}},
      {6000000, {{3, sear::outputs_t::PWM, 64 / 255.0}, four, {44, sear::outputs_t::SERVO, 1500e-6}}},
      {16000000, {{3, sear::outputs_t::PWM, 200 / 255.0}, four, {44, sear::outputs_t::SERVO, 1500e-6}}},
      {26000000, {{3, sear::outputs_t::LEVEL, 0}, four, {44, sear::outputs_t::SERVO, 2000e-6}}},
      {36000000, {{3, sear::outputs_t::PWM, 128 / 255.0}, four, {44, sear::outputs_t::SERVO, 2000e-6}}},
      {46000000, {{3, sear::outputs_t::LEVEL, 1}, four, {44, sear::outputs_t::SERVO, 0}}},
      {56000000, {four, {44, sear::outputs_t::SERVO, 0}}},  // pin 3 is an input again
  };
  ASSERT_EQ(outputs.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) {
    const auto& m = outputs[k];
    EXPECT_EQ(m.time_ns, expected[k].first);
    ASSERT_EQ(m.count, static_cast<int>(expected[k].second.size())) << "at " << m.time_ns;
    for (int i = 0; i < m.count; ++i) {
      const Pin& want = expected[k].second[static_cast<std::size_t>(i)];
      EXPECT_EQ(m.pin[i], want.pin) << "at " << m.time_ns;
      EXPECT_EQ(m.drive[i], want.drive) << "pin " << want.pin << " at " << m.time_ns;
      EXPECT_DOUBLE_EQ(m.value[i], want.value) << "pin " << want.pin << " at " << m.time_ns;
    }
  }
}

// SEAR/CAN/<bus> carries the frames the run's candump log holds, in the same order with the same
// identifiers and data: two MCUs queue 0x200 and 0x100 at once; 0x100 wins arbitration, and 0x200
// starts after the 3 recessive bits of intermission, 6 us at 500 kbit/s (ISO 11898-1).
TEST(Lcm, CanMessagesCarryTheBusFramesAsTheCandumpLogDoes) {
  TempDir dir;
  const auto mcu = [](const std::string& name, const char* firmware) {
    return "    <mcu name=\"" + name + "\">\n      <firmware executable=\"" + firmware +
           "\"/>\n      <can bus=\"body\"/>\n    </mcu>\n";
  };
  std::string project = rover_project(mcu("a", CAN_PROBE_200) + mcu("b", CAN_PROBE_100), "", 0.3);
  project = replaced(project, "  <world", "  <can_bus name=\"body\" bitrate=\"500000\"/>\n  <world");
  const SearRun run = run_sear(dir, project, "-q --lcm-log " + (dir.path() / "run.lcmlog").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::vector<sear::can_frame_t> frames;
  for (const auto& m : decoded<sear::can_t>(read_log((dir.path() / "run.lcmlog").string()), "SEAR/CAN/body")) {
    EXPECT_EQ(m.bus, "body");
    for (const auto& f : m.frames) {
      EXPECT_LE(f.end_ns, m.time_ns);
      frames.push_back(f);
    }
  }
  std::vector<std::string> candump;
  for (const auto& line : lines_of(run.file("body.candump.log"))) {
    char frame[64];
    if (std::sscanf(line.c_str(), "(%*f) %*s %63s", frame) == 1) candump.push_back(frame);
  }
  ASSERT_EQ(frames.size(), 2u);
  ASSERT_EQ(candump.size(), frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    char text[64];
    int n = std::snprintf(text, sizeof text, "%03X#", static_cast<unsigned>(frames[i].id));
    for (int b = 0; b < frames[i].dlc; ++b)
      n += std::snprintf(text + n, sizeof text - static_cast<std::size_t>(n), "%02X", frames[i].data[b]);
    EXPECT_EQ(text, candump[i]);
    EXPECT_FALSE(frames[i].extended);
    EXPECT_TRUE(frames[i].acked);
  }
  EXPECT_EQ(frames[0].id, 0x100);
  EXPECT_EQ(frames[1].start_ns - frames[0].end_ns, 3 * 2000);
}

}  // namespace
}  // namespace sear::test
