// Sharp GP2D12 rangers end to end: the world's distance, the datasheet's curve, the MCU's 10-bit
// ADC against its 5 V reference, as a firmware reads them.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include "devices/sharp_gp2d12.h"
#include "model_run.hpp"

namespace sear::test {
namespace {

TEST(Gp2d12ThroughTheAdc, ReadingsAt10_20_40And80cmFollowTheDatasheetCurve) {
  // Four single-ray rangers side by side on the rover's nose, each facing a thin box at its own
  // distance: 10, 20, 40 and 80 cm from the sensor to the box's face.
  const double distances[] = {0.10, 0.20, 0.40, 0.80};
  const double ys[] = {-0.075, -0.025, 0.025, 0.075};
  std::string mcu = std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + IR_PROBE + "\"/>\n";
  std::string boxes;
  for (int i = 0; i < 4; ++i) {
    mcu += "      <gp2d12 name=\"ir" + std::to_string(i) + "\" adc=\"" + std::to_string(i) + "\" pos=\"0.15 " +
           std::to_string(ys[i]) + " 0.02\" half_angle_deg=\"0\" noise_v=\"0\"/>\n";
    boxes += "    <box name=\"target" + std::to_string(i) + "\" pos=\"" + std::to_string(0.15 + distances[i] + 0.01) + " " +
             std::to_string(ys[i]) + "\" size=\"0.02 0.03 0.3\"/>\n";
  }
  mcu += "    </mcu>\n";
  TempDir dir;
  // A trace row every step, so that the pose each measurement saw is known.
  const auto run = run_sear(dir, rover_project(mcu, boxes, 0.55), "--trace-rate 1000");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto lines = lines_of(run.file("rover.main.console.log"));
  ASSERT_GE(lines.size(), 5u);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(lines.back(), m, std::regex("^0\\.5\\d+ adc (\\d+) (\\d+) (\\d+) (\\d+)$")))
      << lines.back();
  // Read at about 502 ms: the measurement of 497.9 ms (13 x 38.3 ms), taken on the world as it
  // was at the start of its 1 ms step. The boxes' faces are at x = 0.15 m + distance; the
  // distance along each ray follows from the pose (trace: 1e-6 m and rad, so 5e-6 m covers it).
  const Trace trace(run.file("trace_rover.csv"));
  const Pose pose = pose_at(trace, 13 * GP2D12_PERIOD_NS / 1000000 * 1000);
  for (int i = 0; i < 4; ++i) {
    const double d = axis_distance_to_x_plane(pose, {0.15, ys[i], 0.02}, 0.15 + distances[i]);
    ASSERT_NEAR(d, distances[i], 0.002);  // the rover sits where it was put, to 2 mm
    const unsigned code = static_cast<unsigned>(std::stoul(m[i + 1]));
    // The model's curve (hal/devices) quantised by the ADC against 5 V: at most one code apart
    // over the 10 um the pose leaves open (the curve is under 0.2 V/cm here, 0.4 code per 10 um).
    EXPECT_GE(code, adc_code(gp2d12_output_v(d + 5e-6), 5.0)) << "at " << distances[i] * 100 << " cm";
    EXPECT_LE(code, adc_code(gp2d12_output_v(d - 5e-6), 5.0)) << "at " << distances[i] * 100 << " cm";
    // And the datasheet, read independently of the model: 0.4 V typical at 80 cm and 2.0 V more
    // at 10 cm (electro-optical characteristics); about 1.37 V at 20 cm and 0.76 V at 40 cm (the
    // figure "analog output voltage vs. distance", +-0.08 V for reading it), moved by the
    // curve's slope over the rover's offset from the nominal distance (under 0.2 V/cm x 2 mm).
    const double volts[] = {2.40, 1.37, 0.76, 0.40}, reading_v[] = {0.0, 0.08, 0.08, 0.0};
    EXPECT_NEAR(code * 5.0 / 1024, volts[i], reading_v[i] + 0.2 * 100 * std::abs(d - distances[i]) + 5.0 / 1024)
        << "at " << distances[i] * 100 << " cm";
  }
  // The curve falls with distance: each farther target reads lower.
  EXPECT_GT(std::stoi(m[1]), std::stoi(m[2]));
  EXPECT_GT(std::stoi(m[2]), std::stoi(m[3]));
  EXPECT_GT(std::stoi(m[3]), std::stoi(m[4]));
}

TEST(Gp2d12ThroughTheAdc, TheOutputChangesOnlyAtEachNew38Point3msMeasurement) {
  // The rover drives towards a wall on a script while its firmware reads the ranger every
  // millisecond: each change of reading must come from a measurement at k * 38.3 ms.
  const std::string mcu = std::string("    <script>\n      <motor t=\"0\" name=\"left\" duty=\"0.5\"/>\n"
                                      "      <motor t=\"0\" name=\"right\" duty=\"0.5\"/>\n    </script>\n"
                                      "    <mcu name=\"main\">\n      <firmware executable=\"") +
                          ADC_WATCH + "\"/>\n      <gp2d12 name=\"ir\" adc=\"0\" pos=\"0.15 0 0.02\"/>\n    </mcu>\n";
  TempDir dir;
  const auto run = run_sear(dir, rover_project(mcu, "    <wall name=\"w\" from=\"1.2 -1\" to=\"1.2 1\" height=\"0.4\"/>\n", 1.5));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto lines = lines_of(run.file("rover.main.console.log"));
  int changes = 0;
  std::smatch m;
  for (const auto& line : lines) {
    ASSERT_TRUE(std::regex_search(line, m, std::regex(" (\\d+) (\\d+)$"))) << line;
    const double t_us = std::stod(m[1]);
    if (changes++ == 0) continue;  // the first reading, not a change
    // Read once a loop: micros() (3.125 us), adc_read (104 us from its call), delay_ms(1), so
    // 1107.125 us apart; the change is seen at the first read after the measurement.
    const double since = std::fmod(t_us, 38300.0);
    EXPECT_LT(since, 1107.125) << "a change at " << t_us << " us, " << since << " us after a measurement";
  }
  // Approaching at about 0.35 m/s, nearly every one of the 39 measurements reads differently.
  EXPECT_GE(changes, 30);
}

}  // namespace
}  // namespace sear::test
