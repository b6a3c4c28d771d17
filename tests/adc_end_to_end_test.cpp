// Sharp rangers end to end, as a firmware sees them: the world's distance, the device model
// (hal/devices, linked here so the expected volts are the model's own, not a copy of its curve),
// the MCU's ADC under each reference and resolution, and the GP2D15's hysteresis at the pin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>

#include "devices/sharp_gp2d12.h"
#include "devices/sharp_gp2d15.h"
#include "model_run.hpp"

namespace sear::test {
namespace {

// Where the bundled rover carries the rangers of these tests: on its nose, 2 cm above the
// chassis centre (chassis frame, m).
constexpr double kMountX = 0.15;
constexpr double kMountZ = 0.02;

// The chassis pose is read from the trace, printed to 1e-6 m and 1e-6 rad: the sensor-to-face
// distance is known to about 2e-6 m (0.5e-6 from x, 0.02 m lever times 0.5e-6 rad of pitch, the
// rest second order). 5e-6 m leaves room; on the steepest part of the curve used (10 cm, about
// 0.15 V/cm) that is 0.08 mV, under a tenth of a 10-bit code at the lowest reference.
constexpr double kDistanceUncertaintyM = 5e-6;

struct CodeRange {
  unsigned lo, hi;
};

// The codes a GP2D12 can give for a distance between near_m and far_m, each +- the uncertainty:
// the curve falls monotonically beyond its 8 cm peak, so the ends of the interval bound it.
CodeRange gp2d12_codes(double near_m, double far_m, double vref, int bits) {
  const unsigned lo = adc_code(gp2d12_output_v(far_m + kDistanceUncertaintyM), vref, bits);
  const unsigned hi = adc_code(gp2d12_output_v(near_m - kDistanceUncertaintyM), vref, bits);
  return {lo, hi};
}

TEST(AdcEndToEnd, TheDeviceModelHoldsTheDatasheetTableAt10And80cm) {
  // Sharp GP2D12 electro-optical characteristics: Vo at 80 cm typ 0.4 V, and dVo from 80 to
  // 10 cm typ 2.0 V. The readings below are computed from this model function, so it is held to
  // the datasheet here, where it matters to them.
  EXPECT_NEAR(gp2d12_output_v(0.80), GP2D12_V80_TYP_V, 1e-12);
  EXPECT_NEAR(gp2d12_output_v(0.10), GP2D12_V80_TYP_V + GP2D12_DELTA_V_TYP_V, 1e-12);
  EXPECT_DOUBLE_EQ(GP2D12_V80_TYP_V, 0.40);
  EXPECT_DOUBLE_EQ(GP2D12_DELTA_V_TYP_V, 2.0);
}

TEST(AdcEndToEnd, Gp2d12ReadingsUnderEveryReferenceAndResolutionMatchTheModelToTheCode) {
  // Four noiseless single-ray GP2D12s side by side, facing thin boxes at 10 and 80 cm (the
  // datasheet's table points) and at 17 and 33 cm (between the curve's points, where its
  // interpolation shows). The AREF pin is at 3.0 V, not the board's default 3.3 V.
  const double nominal[] = {0.10, 0.17, 0.33, 0.80};
  const double ys[] = {-0.075, -0.025, 0.025, 0.075};
  const double aref_v = 3.0, avcc_v = 5.0;
  std::string mcu = std::string("    <mcu name=\"main\" aref=\"3.0\">\n      <firmware executable=\"") + ADC_PROBE + "\"/>\n";
  std::string boxes;
  double face_x[4];
  for (int i = 0; i < 4; ++i) {
    face_x[i] = kMountX + nominal[i];
    mcu += "      <gp2d12 name=\"ir" + std::to_string(i) + "\" adc=\"" + std::to_string(i) + "\" pos=\"0.15 " +
           std::to_string(ys[i]) + " 0.02\" half_angle_deg=\"0\" noise_v=\"0\"/>\n";
    boxes += "    <box name=\"target" + std::to_string(i) + "\" pos=\"" + std::to_string(face_x[i] + 0.01) + " " +
             std::to_string(ys[i]) + "\" size=\"0.02 0.03 0.3\"/>\n";
  }
  mcu += "    </mcu>\n";
  TempDir dir;
  // A trace row every step, so that the pose each measurement saw is known.
  const auto run = run_sear(dir, rover_project(mcu, boxes, 0.5), "--trace-rate 1000");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Trace trace(run.file("trace_rover.csv"));
  // The probe reads from 400 ms on; the measurements it can see are those of 383.0 and 421.3 ms
  // (38.3 ms cycle), each taken on the world as it was at the start of its 1 ms step.
  // The unpowered rover creeps a little as it settles (tens of micrometres between the two), so
  // the readings are held to the codes of the distances both measurements saw, and everything
  // between them.
  double near[4], far[4];
  for (int i = 0; i < 4; ++i) {
    const Vec3 mount{kMountX, ys[i], kMountZ};
    const double d383 = axis_distance_to_x_plane(pose_at(trace, 383000), mount, face_x[i]);
    const double d421 = axis_distance_to_x_plane(pose_at(trace, 421000), mount, face_x[i]);
    near[i] = std::min(d383, d421);
    far[i] = std::max(d383, d421);
    ASSERT_LT(far[i] - near[i], 1e-4) << "sensor " << i << ": the rover is still moving";
    ASSERT_NEAR(near[i], nominal[i], 0.002) << "sensor " << i;  // the rover sits where it was put, to 2 mm
  }
  const std::string console = run.file("rover.main.console.log");
  ASSERT_NE(console.find(" done\n"), std::string::npos) << console;
  const double vrefs[] = {avcc_v, aref_v, 1.1};  // ADC_REF_AVCC, ADC_REF_EXTERNAL, ADC_REF_1V1
  int clipped = 0;
  for (const int bits : {10, 8}) {
    for (int ref = 0; ref < 3; ++ref) {
      std::smatch m;
      const std::regex line(" ref " + std::to_string(ref) + " bits " + std::to_string(bits) +
                            ": (\\d+) (\\d+) (\\d+) (\\d+)\n");
      ASSERT_TRUE(std::regex_search(console, m, line)) << "ref " << ref << " bits " << bits << "\n" << console;
      for (int i = 0; i < 4; ++i) {
        const unsigned code = static_cast<unsigned>(std::stoul(m[i + 1]));
        const CodeRange expected = gp2d12_codes(near[i], far[i], vrefs[ref], bits);
        EXPECT_GE(code, expected.lo) << "ref " << ref << ", " << bits << " bits, " << near[i] * 100 << " cm";
        EXPECT_LE(code, expected.hi) << "ref " << ref << ", " << bits << " bits, " << near[i] * 100 << " cm";
        EXPECT_LE(expected.hi - expected.lo, 1u);  // the model pins each reading to one or two codes
        if (ref == 2 && gp2d12_output_v(far[i]) > 1.1) {
          // Above the 1.1 V reference the reading is full scale.
          EXPECT_EQ(code, bits == 10 ? 1023u : 255u) << near[i] * 100 << " cm";
          ++clipped;
        }
      }
    }
  }
  EXPECT_EQ(clipped, 4);  // 10 and 17 cm, at both resolutions: the clipping was exercised
}

TEST(AdcEndToEnd, TheGp2d15SwitchesOnBelowItsDistanceAndOffOnlyBeyondTheHysteresis) {
  // A GP2D15 with a non-default judgement distance (22 cm) and hysteresis (3 cm) on the rover's
  // nose, 40 cm from a wall. The rover creeps towards it, then backs away; the firmware reads the
  // pin every millisecond. Each measurement k, at k * 38.3 ms, judges the distance at the start
  // of its 1 ms step; the rover moves about 1 cm per measurement, well under the 3 cm hysteresis.
  const double sw = 0.22, hyst = 0.03;
  const double face = kMountX + 0.40;
  const std::string mcu = std::string(
                              "    <script>\n"
                              "      <motor t=\"0\" name=\"left\" duty=\"0.35\"/>\n"
                              "      <motor t=\"0\" name=\"right\" duty=\"0.35\"/>\n"
                              "      <motor t=\"1.3\" name=\"left\" duty=\"0.35\" dir=\"reverse\"/>\n"
                              "      <motor t=\"1.3\" name=\"right\" duty=\"0.35\" dir=\"reverse\"/>\n"
                              "    </script>\n"
                              "    <mcu name=\"main\">\n      <firmware executable=\"") +
                          SWITCH_WATCH +
                          "\"/>\n"
                          "      <gp2d15 name=\"front\" pin=\"22\" pos=\"0.15 0 0.02\" half_angle_deg=\"0\" "
                          "switch_distance=\"0.22\" hysteresis=\"0.03\"/>\n    </mcu>\n";
  const std::string wall = "    <box name=\"target\" pos=\"" + std::to_string(face + 0.01) + " 0\" size=\"0.02 0.6 0.3\"/>\n";
  TempDir dir;
  const auto run = run_sear(dir, rover_project(mcu, wall, 3.0), "--trace-rate 1000");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Trace trace(run.file("trace_rover.csv"));
  const auto lines = lines_of(run.file("rover.main.console.log"));
  // The first reading (LOW: nothing within 22 cm), one switch on, one switch off: no chatter.
  ASSERT_EQ(lines.size(), 3u) << run.file("rover.main.console.log");
  const std::int64_t period_ns = GP2D15_PERIOD_NS, step_ns = 1000000, call_ns = 3125;
  // The distance measurement k judged: its step began at the whole step at or before k * period.
  const auto distance_of = [&](std::int64_t k) {
    const std::int64_t step_start = (k * period_ns) / step_ns * step_ns;
    return axis_distance_to_x_plane(pose_at(trace, step_start / 1000), {kMountX, 0, kMountZ}, face);
  };
  const double tol = kDistanceUncertaintyM;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::smatch m;
    ASSERT_TRUE(std::regex_search(lines[i], m, std::regex(" (\\d+) ([01])$"))) << lines[i];
    const int level = std::stoi(m[2]);
    EXPECT_EQ(level, i == 1 ? 1 : 0) << lines[i];
    if (i == 0) continue;
    // micros() is printed; digital_read() came one call (3125 ns) after it, somewhere in that
    // microsecond. The new level came from the last measurement at or before the read: the one
    // before would have been seen by the read a millisecond earlier.
    const std::int64_t read_lo = std::stoll(m[1]) * 1000 + call_ns, read_hi = read_lo + 999;
    const std::int64_t k = read_lo / period_ns;
    ASSERT_EQ(read_hi / period_ns, k) << "the read straddles a measurement: " << lines[i];
    const double now = distance_of(k), before = distance_of(k - 1);
    if (level == 1) {  // approaching: H once closer than the switching distance
      EXPECT_LT(now, sw + tol) << "switched on at " << now * 100 << " cm";
      EXPECT_GE(before, sw - tol) << "already closer than " << sw * 100 << " cm at " << before * 100 << " cm";
    } else {  // receding: L only once beyond switch distance + hysteresis
      EXPECT_GT(now, sw + hyst - tol) << "switched off at " << now * 100 << " cm";
      EXPECT_LE(before, sw + hyst + tol) << "still H beyond " << (sw + hyst) * 100 << " cm at " << before * 100 << " cm";
    }
  }
  // It did get close, and back out: between the two switches the distance went under 22 cm.
  double closest = 1.0;
  for (const auto t_us : trace.times_us())
    closest = std::min(closest, axis_distance_to_x_plane(pose_at(trace, t_us), {kMountX, 0, kMountZ}, face));
  EXPECT_LT(closest, sw - 0.02);
}

}  // namespace
}  // namespace sear::test
