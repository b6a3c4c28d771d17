// Servo pulses on a pin with no timer, read off the wire (sim/runtime/servo_wire.cpp): pulses a
// firmware makes with digital_write and delays on the native engine, and those the AVR target's
// timer5 interrupt makes for servo_write_us (hal/targets/avr/soft_servo.c) on the AVR engine,
// turn a positional servo to the pulse's angle; the trace shows the width read; when the
// pulses stop the servo lets go.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "firmware_run.hpp"
#include "model_run.hpp"
#include "runtime/servo_wire.hpp"
#include "urdf/urdf_files.hpp"

namespace sear::test {
namespace {

constexpr int kPin = 30;             // PC7: no timer channel
constexpr double kRangeDeg = 90;     // the servo's travel over 800..2200 us
constexpr double kCentreUs = 1500, kHalfSpanUs = 700;
constexpr double kCycleNs = 62.5;    // 16 MHz
constexpr std::int64_t kMs = 1000000;

std::string firmware(const char* name) { return std::string(SERVO_TEST_FIRMWARE) + "/" + name; }

// A 20 kg cart on two free wheels and two ball casters, with a 0.1 kg head panning about z on
// a revolute joint, turned by a positional servo (90 degrees over 800..2200 us, 0.2 s per 60
// degrees, so that neither 1500 nor 2000 us and what a call adds meets an end) whose pulses come
// from pin 30 of the MCU.
std::string rig_project(const TempDir& dir, const std::string& engine, const std::string& sources,
                        double duration_s = 2.2, const std::string& defines = "") {
  const auto path = dir.path() / "rig.urdf";
  std::ofstream(path) << rig_urdf(R"(  <link name="head">
    <collision><origin xyz="0 0 0.015"/><geometry><box size="0.04 0.1 0.03"/></geometry></collision>
    <inertial><origin xyz="0 0 0.015"/><mass value="0.1"/>
      <inertia ixx="9.08e-5" ixy="0" ixz="0" iyy="2.08e-5" iyz="0" izz="9.67e-5"/></inertial>
  </link>
  <joint name="pan_joint" type="revolute"><parent link="base_link"/><child link="head"/>
    <origin xyz="0 0 0.025"/><axis xyz="0 0 1"/><limit lower="-1.2" upper="1.2" effort="2" velocity="10"/></joint>)");
  std::ostringstream p;
  p << "<project name=\"servo_pin\">\n"
    << "  <run duration=\"" << duration_s << "\" seed=\"1\" trace_rate=\"1000\"/>\n"
    << "  <world step=\"0.001\"><terrain type=\"flat\"/></world>\n"
    << "  <robot name=\"rig\" urdf=\"" << path.string() << "\">\n"
    << "    <wheel name=\"left\" joint=\"left_wheel_joint\"/>\n"
    << "    <wheel name=\"right\" joint=\"right_wheel_joint\"/>\n"
    << "    <caster link=\"front_caster\"/>\n    <caster link=\"rear_caster\"/>\n"
    << "    <servo name=\"pan\" joint=\"pan_joint\" range_deg=\"" << kRangeDeg << "\" min_pulse_us=\""
    << kCentreUs - kHalfSpanUs << "\" max_pulse_us=\"" << kCentreUs + kHalfSpanUs
    << "\" speed_s_per_60deg=\"0.2\" torque=\"0.5\"/>\n"
    << "    <mcu name=\"main\" engine=\"" << engine << "\">\n"
    << "      <firmware sources=\"" << sources << "\" defines=\"" << defines << "\"/>\n"
    << "      <servo name=\"pan\" pin=\"" << kPin << "\"/>\n"
    << "    </mcu>\n  </robot>\n</project>\n";
  return p.str();
}

// The servo's angle for a pulse: linear over its range about the 1500 us centre.
double angle_of(double pulse_us) { return (pulse_us - kCentreUs) / kHalfSpanUs * 0.5 * kRangeDeg * M_PI / 180; }

struct Pulse {
  std::int64_t rise_ns, fall_ns;
};

// The HIGHs on pin 30 in the run's VCD.
std::vector<Pulse> pulses_of(const SearRun& run) {
  std::vector<Pulse> pulses;
  std::int64_t rise = -1;
  for (const auto& c : vcd_changes(run.file("rig.main.pins.vcd"), vcd_id_of_pin(kPin))) {
    if (c.value == '1') rise = c.time;
    if (c.value == '0' && rise >= 0) {
      pulses.push_back({rise, c.time});
      rise = -1;
    }
  }
  return pulses;
}

// The trace's rows (1 ms apart) between two times, in whole microseconds.
std::vector<long long> rows_between(const Trace& trace, double from_s, double to_s) {
  std::vector<long long> rows;
  for (long long t : trace.times_us())
    if (t >= std::llround(from_s * 1e6) && t <= std::llround(to_s * 1e6)) rows.push_back(t);
  return rows;
}

// Each pulse's width reaches the servo at its falling edge: the trace row at the end of the step
// that edge falls in shows the width (to the 0.1 us the trace prints).
void expect_trace_follows_the_wire(const Trace& trace, const std::vector<Pulse>& pulses) {
  for (std::size_t k = 0; k + 1 < pulses.size(); ++k) {
    const double width_us = static_cast<double>(pulses[k].fall_ns - pulses[k].rise_ns) * 1e-3;
    const long long row_us = (pulses[k].fall_ns / kMs + 1) * 1000;  // the end of the step it falls in
    ASSERT_TRUE(trace.has(row_us)) << row_us;
    EXPECT_NEAR(trace.at(row_us, "servo_pan_pulse_us"), width_us, 0.05 + 1e-9) << "pulse " << k << " at " << row_us << " us";
  }
}

// The servo lets go once no pulse has started for 50 ms: 0 from the step in which 50 ms after
// the last rising edge falls, the last width before it.
void expect_off_50ms_after_the_last_pulse(const Trace& trace, const std::vector<Pulse>& pulses) {
  ASSERT_FALSE(pulses.empty());
  const std::int64_t lapse_ns = pulses.back().rise_ns + 50 * kMs;
  const long long before_us = (lapse_ns / kMs) * 1000, after_us = before_us + 1000;
  const double last_us = static_cast<double>(pulses.back().fall_ns - pulses.back().rise_ns) * 1e-3;
  EXPECT_NEAR(trace.at(before_us, "servo_pan_pulse_us"), last_us, 0.05 + 1e-9);
  EXPECT_EQ(trace.at(after_us, "servo_pan_pulse_us"), 0);
  EXPECT_EQ(trace.last("servo_pan_pulse_us"), 0);
}

TEST(ServoPin, PulsesMadeWithDigitalWriteAndDelaysTurnTheServo) {
  TempDir dir;
  const SearRun run = run_sear(dir, rig_project(dir, "native", firmware("servo_bitbang.c")));
  ASSERT_EQ(run.exit_code, 0) << run.err << run.out;
  const Trace trace(run.file("trace_rig.csv"));
  // Each HIGH lasts its delay and the cost of the digital_write(HIGH) call before it (50 cycles
  // at 16 MHz): the edges are stamped with their calls' instants, and a delay counts from its own.
  const double call_us = 50 / 16.0;
  const std::vector<Pulse> pulses = pulses_of(run);
  ASSERT_EQ(pulses.size(), 100u);
  for (std::size_t k = 0; k < pulses.size(); ++k)
    EXPECT_EQ(pulses[k].fall_ns - pulses[k].rise_ns, std::llround(((k < 50 ? 1500 : 2000) + call_us) * 1000)) << k;
  expect_trace_follows_the_wire(trace, pulses);
  for (long long t : rows_between(trace, 0.1, 1.0)) ASSERT_NEAR(trace.at(t, "servo_pan_pulse_us"), 1500 + call_us, 0.05) << t;
  for (long long t : rows_between(trace, 1.1, 2.0)) ASSERT_NEAR(trace.at(t, "servo_pan_pulse_us"), 2000 + call_us, 0.05) << t;
  // The head sits at the pulse's angle: 1503.1 us is 0.20 degrees off centre, 2003.1 us 32.3
  // degrees. The servo's output slews there in 0.11 s at most (60 degrees per 0.2 s), and the
  // joint's loop (20 /s, urdf_joint_test) closes its lag of speed / gain = 0.26 rad to
  // exp(-20 * 0.8) of it well before the times read. The trace's six decimals round by up to
  // 5e-7 rad and the solver leaves the joint's row under load 1.5e-8 rad off (urdf_joint_test),
  // so 1e-6, a thousandth of the 1.1 mrad that 1 us of pulse is worth (pi/4 over 700 us).
  EXPECT_NEAR(trace.at(1000000, "joint_pan_joint_pos"), angle_of(1500 + call_us), 1e-6);
  EXPECT_NEAR(trace.at(2000000, "joint_pan_joint_pos"), angle_of(2000 + call_us), 1e-6);
  expect_off_50ms_after_the_last_pulse(trace, pulses);
}

// The AVR target's timer5 interrupt (hal/targets/avr/soft_servo.c) raises and lowers the pin with
// its first two stores, 11 cycles apart (avr-gcc -Os), so a pulse is its counts of 0.5 us less
// those 11 cycles. The compare's entry can be held up at either edge by what holds interrupts
// off: in this firmware, at worst timer0's overflow handler for millis (101 cycles from its
// vector to its reti, avr-objdump of time.c) and the one instruction run after a reti (up to 5
// cycles), with the 4 extra cycles of the longest instruction the compare may land in: 110
// cycles, 6.9 us, either way.
constexpr double kStoresApartNs = 11 * kCycleNs;
constexpr double kLatencyNs = 110 * kCycleNs;

TEST(ServoPin, ServoWriteUsOnAPinWithoutATimerPulsesItFromTimer5OnTheAvrTarget) {
  TempDir dir;
  const SearRun run = run_sear(dir, rig_project(dir, "avr", firmware("servo_any_pin.c")));
  ASSERT_EQ(run.exit_code, 0) << run.err << run.out;
  const Trace trace(run.file("trace_rig.csv"));
  const std::vector<Pulse> pulses = pulses_of(run);
  // 20 ms frames from just after hal_init for 2 s: 100 pulses, the first 50 of 1500 us.
  ASSERT_EQ(pulses.size(), 100u);
  std::vector<std::int64_t> widths, frames;
  for (std::size_t k = 0; k < pulses.size(); ++k) {
    const double asked_ns = (k < 50 ? 1500 : 2000) * 1000.0;
    const auto width = pulses[k].fall_ns - pulses[k].rise_ns;
    EXPECT_NEAR(static_cast<double>(width), asked_ns - kStoresApartNs, kLatencyNs) << "pulse " << k;
    widths.push_back(static_cast<std::int64_t>(std::llround(static_cast<double>(width) - asked_ns)));
    if (k > 0) {
      const auto frame = pulses[k].rise_ns - pulses[k - 1].rise_ns;
      EXPECT_NEAR(static_cast<double>(frame), 20e6, kLatencyNs) << "frame before pulse " << k;
      frames.push_back(frame);
    }
  }
  // Most edges meet no other interrupt: then a width is exact to the VCD's 1 ns rounding of
  // the 62.5 ns cycles, and so is the 40000-count frame.
  std::nth_element(widths.begin(), widths.begin() + 50, widths.end());
  EXPECT_NEAR(static_cast<double>(widths[50]), -kStoresApartNs, 1.0);
  std::nth_element(frames.begin(), frames.begin() + 49, frames.end());
  EXPECT_NEAR(static_cast<double>(frames[49]), 20e6, 1.0);
  expect_trace_follows_the_wire(trace, pulses);
  // The head at the widths' angles, the solver's 2e-4 rad as on the native engine and up to the
  // latency's worth (1.12 mrad a microsecond) for the last pulses' jitter.
  const double jitter_rad = angle_of(kCentreUs + kLatencyNs * 1e-3) - angle_of(kCentreUs);
  EXPECT_NEAR(trace.at(1000000, "joint_pan_joint_pos"), angle_of(1500 - kStoresApartNs * 1e-3), 2e-4 + jitter_rad);
  EXPECT_NEAR(trace.at(2000000, "joint_pan_joint_pos"), angle_of(2000 - kStoresApartNs * 1e-3), 2e-4 + jitter_rad);
  // servo_write_us(30, 0) at 2 s stops the pulses; the servo lets go 50 ms after the last.
  EXPECT_LT(pulses.back().rise_ns, 2000 * kMs);
  expect_off_50ms_after_the_last_pulse(trace, pulses);
  EXPECT_EQ(run.out.find("servo 'pan'"), std::string::npos) << run.out;  // the wiring report has it driven
}

// The decoder's bounds, each met exactly and missed by a nanosecond.
TEST(ServoWire, TakesHighsOf400To2600UsAtLeast3MsApartAndLetsGo50MsAfterTheLast) {
  ServoWires wires({kPin});
  const auto pulse = [&](std::int64_t rise_ns, std::int64_t width_ns) {
    wires.level(kPin, true, rise_ns);
    return wires.level(kPin, false, rise_ns + width_ns);
  };
  EXPECT_EQ(wires.pulse_us(kPin, 0), 0);
  EXPECT_FALSE(pulse(0, 399'999));                      // too short: no servo takes it
  EXPECT_EQ(wires.pulse_us(kPin, kMs), 0);
  EXPECT_TRUE(pulse(3 * kMs, 400'000));                 // 3 ms after the last rise: a frame
  EXPECT_EQ(wires.pulse_us(kPin, 4 * kMs), 400);
  EXPECT_FALSE(pulse(6 * kMs - 1, 1'000'000));          // a frame a nanosecond under 3 ms: PWM
  EXPECT_EQ(wires.pulse_us(kPin, 8 * kMs), 400);        // and the servo keeps the last pulse
  EXPECT_FALSE(pulse(10 * kMs, 2'600'001));             // too long: a level
  EXPECT_TRUE(pulse(20 * kMs, 2'600'000));
  EXPECT_EQ(wires.pulse_us(kPin, 70 * kMs), 2600);      // 50 ms after its rise it still holds
  EXPECT_EQ(wires.pulse_us(kPin, 70 * kMs + 1), 0);     // and then lets go
  // A width announced without edges (servo_write_us, a PWM timer) holds until the next pulse
  // read on the wire, and does not lapse; the later of the two wins.
  wires.announced(kPin, 1500);
  EXPECT_EQ(wires.pulse_us(kPin, 10'000 * kMs), 1500);
  EXPECT_TRUE(pulse(10'000 * kMs, 1'200'000));
  EXPECT_EQ(wires.pulse_us(kPin, 10'001 * kMs), 1200);
  wires.announced(kPin, 0);
  EXPECT_EQ(wires.pulse_us(kPin, 10'002 * kMs), 0);
  // A pin no servo is wired to is not read.
  EXPECT_FALSE(wires.level(kPin + 1, true, 0) || wires.level(kPin + 1, false, kMs));
  EXPECT_EQ(wires.pulse_us(kPin + 1, kMs), 0);
}

TEST(ServoPin, APinHeldHighIsNoServoPulsesAndTheWiringReportSaysSo) {
  TempDir dir;
  const SearRun run = run_sear(dir, rig_project(dir, "native", firmware("servo_held_high.c"), 0.2));
  ASSERT_EQ(run.exit_code, 0) << run.err << run.out;
  const Trace trace(run.file("trace_rig.csv"));
  for (long long t : rows_between(trace, 0.001, 0.2)) ASSERT_EQ(trace.at(t, "servo_pan_pulse_us"), 0) << t;
  EXPECT_NE(run.out.find("servo 'pan': its pin 30 never got servo pulses: the firmware drove it HIGH, but never for "
                         "400..2600 us at a time, 3 ms or more apart"),
            std::string::npos)
      << run.out;
}

// Timer5 makes either the software servo pulses or irq_timer_start's interrupt: whichever comes
// second stops the chip, and the reason is on its console.
TEST(ServoPin, TimerFiveAskedForTwiceStopsTheChipWithTheReasonOnItsConsole) {
  for (const char* defines : {"", "SERVO_FIRST"}) {
    SCOPED_TRACE(defines);
    TempDir dir;
    const SearRun run = run_sear(dir, rig_project(dir, "avr", firmware("servo_timer5_clash.c"), 0.1, defines));
    ASSERT_EQ(run.exit_code, 0) << run.err << run.out;
    const std::string console = run.file("rig.main.console.log");
    EXPECT_NE(console.find("start"), std::string::npos) << console;
    EXPECT_EQ(console.find("not reached"), std::string::npos) << console;
    EXPECT_NE(console.find(*defines ? "irq_timer_start: timer5 makes the servo pulses of the pins without a 16-bit PWM timer"
                                    : "servo_write_us on a pin without a 16-bit PWM timer: timer5 makes those pulses, and "
                                      "irq_timer_start holds it"),
              std::string::npos)
        << console;
    EXPECT_NE(run.out.find("halted at sim time 0.01"), std::string::npos) << run.out;  // after the 10 ms delay
  }
}

}  // namespace
}  // namespace sear::test
