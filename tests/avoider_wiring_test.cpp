// The bundled avoider (firmware_examples/avoider, unmodified) through a scene whose outcome
// depends on its wiring: an obstacle ahead on one side, which the ranger on that side sees and the
// other one does not, so the rover must veer away from it. With the motors' wiring swapped the
// same firmware veers the wrong way, towards the obstacle: the test runs that too and asserts it,
// so the scene is known to tell the two apart.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "model_run.hpp"

namespace sear::test {
namespace {

// The avoider's MCU wired as in firmware_examples/avoider/project.xml (rangers on A0 left and A1
// right, GP2D15 on 22, bump on 2, Motor Shield R3 channel A left and B right), noiseless rangers;
// `swap_motors` puts the left motor on channel B and the right one on channel A.
std::string avoider_mcu(bool swap_motors) {
  const char* left = swap_motors ? "right" : "left";
  const char* right = swap_motors ? "left" : "right";
  return std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + AVOIDER + "\"/>\n" +
         "      <gp2d12 name=\"ir_left\" adc=\"0\" pos=\"0.15 0.06 0.02\" yaw_deg=\"30\" noise_v=\"0\"/>\n"
         "      <gp2d12 name=\"ir_right\" adc=\"1\" pos=\"0.15 -0.06 0.02\" yaw_deg=\"-30\" noise_v=\"0\"/>\n"
         "      <gp2d15 name=\"ir_front\" pin=\"22\" pos=\"0.15 0 0.02\"/>\n"
         "      <bump name=\"bumper\" pin=\"2\" pos=\"0.14 0 -0.01\" width=\"0.18\" reach=\"0.02\"/>\n"
         "      <motor name=\"" + left + "\" pwm=\"3\" dir=\"12\" brake=\"9\"/>\n"
         "      <motor name=\"" + right + "\" pwm=\"11\" dir=\"13\" brake=\"8\"/>\n"
         "    </mcu>\n";
}

// A crate ahead and to one side (side +1 left, -1 right of the rover's heading): the ranger on
// that side, 30 degrees out, meets its near face at about 35 cm, under the avoider's 55 cm veering
// distance; the other ranger and the GP2D15 straight ahead see nothing within their range.
std::string crate(int side) {
  return "    <box name=\"crate\" pos=\"0.6 " + std::to_string(0.32 * side) + "\" size=\"0.3 0.2 0.3\"/>\n";
}

struct Outcome {
  SearRun run;
  double veer_yaw_rad;  // 0.5 s in: 0.4 s into the first veer, which begins at the first reading
  double yaw_rad;       // at the end
  double y_m;
  double x_m;
  std::size_t collisions;
  std::string console;
};

Outcome drive(const TempDir& dir, int side, bool swap_motors) {
  Outcome o{run_sear(dir, rover_project(avoider_mcu(swap_motors), crate(side), 1.5)), 0, 0, 0, 0, 0, ""};
  if (o.run.exit_code != 0) return o;
  const Trace trace(o.run.file("trace_rover.csv"));
  o.veer_yaw_rad = trace.at(500000, "yaw_rad");
  o.yaw_rad = trace.last("yaw_rad");
  o.y_m = trace.last("y_m");
  o.x_m = trace.last("x_m");
  o.collisions = nlohmann::json::parse(o.run.file("summary.json"))["collision_events"].size();
  o.console = o.run.file("rover.main.console.log");
  return o;
}

// The console line after "avoider: ready": what the firmware decided on its first readings.
std::string first_decision(const std::string& console) {
  const auto lines = lines_of(console);
  return lines.size() > 1 && lines[0].find("avoider: ready") != std::string::npos ? lines[1] : "";
}

TEST(AvoiderWiring, ItVeersAwayFromAnObstacleOnEitherSideAndTheWrongWayWithItsMotorsSwapped) {
  // Veering is drive(150, 50): the outer wheel at 150/255 of the supply, the inner one at 50/255.
  // Over about a second of veering the heading turns by tens of degrees; 0.2 rad is a margin far
  // above anything straight driving or settling gives (well under 0.01 rad).
  const double turned = 0.2;
  {
    TempDir dir;
    const auto o = drive(dir, +1, false);
    ASSERT_EQ(o.run.exit_code, 0) << o.run.err;
    // Its first decision, at its first reading: the crate is on the left.
    EXPECT_NE(first_decision(o.console).find(" veering right (L "), std::string::npos) << o.console;
    EXPECT_EQ(o.console.find("veering left"), std::string::npos) << o.console;
    EXPECT_LT(o.veer_yaw_rad, -turned) << "crate on the left: it must turn right (clockwise)";
    EXPECT_LT(o.yaw_rad, -turned);
    EXPECT_LT(o.y_m, 0.0);
    EXPECT_GT(o.x_m, 0.3);  // forwards: direction pins HIGH drive forwards
    EXPECT_EQ(o.collisions, 0u) << o.run.file("summary.json");
  }
  {
    TempDir dir;
    const auto o = drive(dir, -1, false);
    ASSERT_EQ(o.run.exit_code, 0) << o.run.err;
    EXPECT_NE(first_decision(o.console).find(" veering left (L "), std::string::npos) << o.console;
    EXPECT_EQ(o.console.find("veering right"), std::string::npos) << o.console;
    EXPECT_GT(o.veer_yaw_rad, turned) << "crate on the right: it must turn left (counter-clockwise)";
    EXPECT_GT(o.yaw_rad, turned);
    EXPECT_GT(o.y_m, 0.0);
    EXPECT_GT(o.x_m, 0.3);
    EXPECT_EQ(o.collisions, 0u) << o.run.file("summary.json");
  }
  {
    // Motors swapped: the firmware still decides to veer right, and the rover turns left, towards
    // the crate, until the crate fills the GP2D15's view and the firmware's turns (now also the
    // wrong way round) take over. This is what the runs above would show if the wiring were wrong.
    TempDir dir;
    const auto o = drive(dir, +1, true);
    ASSERT_EQ(o.run.exit_code, 0) << o.run.err;
    EXPECT_NE(first_decision(o.console).find(" veering right (L "), std::string::npos) << o.console;
    EXPECT_NE(o.console.find("front near"), std::string::npos) << o.console;  // it faced the crate
    EXPECT_GT(o.veer_yaw_rad, turned) << "swapped motors: it turns towards the crate";
  }
}

}  // namespace
}  // namespace sear::test
