// A URDF's moving joints that are no wheels, live in the simulation: a passive hinge falls onto
// its stop and stays there, damping takes the swing out at the rate c / (2 I), a servo turns its
// joint to the pulse's angle within the URDF's effort, and a slider stops at its upper limit.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "../command_output.hpp"
#include "../firmware_run.hpp"
#include "../temp_dir.hpp"
#include "../test_world.hpp"
#include "scene/project_loader.hpp"
#include "urdf_files.hpp"

namespace sear::test {
namespace {

constexpr double kG = 9.81;
constexpr double kStep_s = 0.001;

// A 0.2 kg ball of 20 mm radius (I = 2/5 m r^2 = 3.2e-5 kg m^2 about its centre) at `xyz` in
// its link, which hangs on `joint` 0.3 m above base_link, turning about the robot's x axis.
constexpr double kBobMass_kg = 0.2;
constexpr double kBobOwnInertia = 0.4 * kBobMass_kg * 0.02 * 0.02;
std::string bob_xml(const std::string& xyz, const std::string& type, const std::string& limit,
                    const std::string& dynamics = "") {
  return fmt::format(R"(
  <link name="bob">
    <collision><origin xyz="{0}"/><geometry><sphere radius="0.02"/></geometry></collision>
    <visual><origin xyz="{0}"/><geometry><sphere radius="0.02"/></geometry></visual>
    <inertial><origin xyz="{0}"/><mass value="0.2"/><inertia ixx="3.2e-5" ixy="0" ixz="0" iyy="3.2e-5" iyz="0" izz="3.2e-5"/></inertial>
  </link>
  <joint name="bob_joint" type="{1}"><parent link="base_link"/><child link="bob"/>
    <origin xyz="0 0 0.3"/><axis xyz="1 0 0"/>{2}{3}</joint>)",
                     xyz, type, limit, dynamics);
}

// The direct solver, the default: the iterative one at its default 20 sweeps leaves a 0.2 kg link
// on a 20 kg cart short of convergence, and its stops and motor rows give (a 40 mrad overshoot
// past a stop, a servo 7 mrad off under load).
struct Rig {
  TempDir dir;
  ProjectDesc project;
  std::unique_ptr<Simulation> sim;
  Rig(const std::string& urdf_extra, const std::string& mapping_extra = "") {
    const std::string path = (dir.path() / "rig.urdf").string();
    write_text(path, rig_urdf(urdf_extra));
    project = project_from_xml(project_xml(R"(step="0.001")", "", R"(
  <robot name="rig" urdf=")" + path + R"(">
    <wheel name="left" joint="left_wheel_joint" material="rubber"/>
    <wheel name="right" joint="right_wheel_joint" material="rubber"/>
    <caster link="front_caster"/>
    <caster link="rear_caster"/>
    )" + mapping_extra + R"(
  </robot>)"));
    sim = std::make_unique<Simulation>(project, 1);
  }
  const ArticulatedJoint& joint(const std::string& name) {
    const auto& joints = project.robots[0].joints;
    for (std::size_t j = 0; j < joints.size(); ++j)
      if (joints[j].joint == name) return sim->robot(0).joint(j);
    throw std::runtime_error("no live joint " + name);
  }
};

TEST(UrdfJoint, PassiveHingeFallsOntoItsStopAndStaysThere) {
  // The bob sticks out level along y at rest; gravity turns it about x towards negative angles
  // (Rx(q) takes +y to +z for positive q), onto the lower stop at -1 rad.
  const double lower = -1.0, length = 0.15;
  Rig rig(bob_xml("0 0.15 0", "revolute", R"(<limit lower="-1.0" upper="0.5" effort="1" velocity="20"/>)"));
  const ArticulatedJoint& j = rig.joint("bob_joint");
  double lowest = 0;
  run_for(*rig.sim, 3.0, [&] { lowest = std::min(lowest, j.position()); });
  // It meets the stop at the speed its fall from level gives it: I w^2 / 2 = m g L sin(1). ODE
  // engages a stop once a step starts past it, so it overshoots by at most one step's travel
  // w h before the stop's ERP pulls it back (10.5 mrad here).
  const double pivot_inertia = kBobOwnInertia + kBobMass_kg * length * length;
  const double impact_radps = std::sqrt(2 * kBobMass_kg * kG * length * std::sin(-lower) / pivot_inertia);
  EXPECT_GE(lowest, lower - impact_radps * kStep_s) << "overshoot " << lower - lowest;
  EXPECT_LT(lowest, lower + 1e-3);  // it did fall all the way
  // At rest on the stop: the gravity torque m g L cos(1) = 0.16 N*m presses it by torque * h *
  // CFM / ERP = 8e-10 rad (world ERP 0.2, CFM 1e-6), which the direct solver gives (7.95e-10
  // measured); the bound leaves 2e-10 for the rest of the step's rounding.
  EXPECT_NEAR(j.position(), lower, 1e-9);
  EXPECT_NEAR(j.rate(), 0.0, 1e-3);
}

// The amplitude of the swing about its hanging rest, at each turning point, with its time.
struct Swing {
  std::vector<std::pair<double, double>> peaks;  // t, |q - rest|
};

Swing swing(const std::string& dynamics, double seconds) {
  // The bob's centre 0.3 rad off the vertical under the pivot: it hangs at q = -0.3 and swings
  // from 0 to -0.6. A continuous joint: no stops.
  const double offset = 0.3, length = 0.15;
  Rig rig(bob_xml(fmt::format("0 {:.17g} {:.17g}", length * std::sin(offset), -length * std::cos(offset)),
                  "continuous", "", dynamics));
  const ArticulatedJoint& j = rig.joint("bob_joint");
  Swing out;
  double last_rate = 0;
  run_for(*rig.sim, seconds, [&] {
    // A turning point is where the rate changes sign; one within 0.1 s of the last (a swing
    // takes 0.39 s) is the same one, its rate dithering about zero as friction grips.
    const double rate = j.rate(), t = static_cast<double>(rig.sim->time_ns()) * 1e-9;
    if ((rate < 0) != (last_rate < 0) && last_rate != 0 && (out.peaks.empty() || t - out.peaks.back().first > 0.1))
      out.peaks.push_back({t, std::abs(j.position() + offset)});
    last_rate = rate;
  });
  return out;
}

// The exponential decay rate of the turning points' amplitude, from the first to the last.
double decay_rate(const Swing& s) {
  const auto& a = s.peaks.front();
  const auto& b = s.peaks.back();
  return std::log(a.second / b.second) / (b.first - a.first);
}

TEST(UrdfJoint, DampingTakesTheSwingOutAtCOverTwoI) {
  const double c = 0.005, length = 0.15;  // N*m*s/rad
  const Swing free = swing("", 4.0);
  const Swing damped = swing(fmt::format(R"(<dynamics damping="{}" friction="0"/>)", c), 4.0);
  ASSERT_GE(free.peaks.size(), 8u);  // a period of 2 pi sqrt(I / (m g L)) = 0.78 s: ten turns in 4 s
  ASSERT_GE(damped.peaks.size(), 8u);
  // Undamped, the swing keeps its 0.3 rad: ODE's semi-implicit Euler step and the joint's
  // error correction lose little energy; the cart, rocking on its tyres, takes some.
  EXPECT_NEAR(free.peaks.front().second, 0.3, 0.01);
  EXPECT_GT(free.peaks.back().second, 0.3 * 0.97);
  // I q'' = -m g L sin q - c q': the amplitude decays as exp(-c t / (2 I)), I about the pivot.
  // The difference from the undamped run takes out what the step and the cart lose anyway;
  // 3 % covers the pendulum's nonlinearity at 0.3 rad (the mean of q'^2 over a swing differs
  // from the linear one's by about q0^2 / 16 = 0.6 %) and the turning points falling between steps.
  const double inertia = kBobOwnInertia + kBobMass_kg * length * length;
  const double expected = c / (2 * inertia);
  EXPECT_NEAR(decay_rate(damped) - decay_rate(free), expected, 0.03 * expected)
      << "damped " << decay_rate(damped) << "/s, free " << decay_rate(free) << "/s";
}

TEST(UrdfJoint, CoulombFrictionTakesTheSwingOutLinearly) {
  // Coulomb friction f takes the energy f * 2A out of each half swing of amplitude A, and
  // m g L (1 - cos A) is the energy at A: each half swing loses 2 f A / (m g L sin A) of its
  // amplitude (2 f / (m g L) = 13.6 mrad for small A), where damping loses a fixed fraction.
  const double f = 0.002, length = 0.15;
  const Swing free = swing("", 3.0);
  const Swing rubbing = swing(fmt::format(R"(<dynamics damping="0" friction="{}"/>)", f), 3.0);
  ASSERT_GE(rubbing.peaks.size(), 8u);
  double expected = 0;
  for (std::size_t k = 0; k + 1 < rubbing.peaks.size(); ++k) {
    const double a = rubbing.peaks[k].second;
    expected += 2 * f * a / (kBobMass_kg * kG * length * std::sin(a));
  }
  const double lost = rubbing.peaks.front().second - rubbing.peaks.back().second;
  const double lost_anyway = free.peaks.front().second - free.peaks[rubbing.peaks.size() - 1].second;
  // 5 %: the turning points fall between 1 ms steps, and the cart rocking on its tyres takes
  // (and gives back) a little of the swing, as the free run's own loss shows.
  EXPECT_NEAR(lost - lost_anyway, expected, 0.05 * expected) << "lost " << lost << " rad, free " << lost_anyway;
}

TEST(UrdfJoint, ServoTurnsItsJointToThePulsesAngle) {
  // A 0.1 kg head panning about z on top of base_link, turned by a positional servo of 160
  // degrees' travel at 0.2 s per 60 degrees.
  Rig rig(R"(
  <link name="head">
    <collision><origin xyz="0 0 0.015"/><geometry><box size="0.04 0.1 0.03"/></geometry></collision>
    <inertial><origin xyz="0 0 0.015"/><mass value="0.1"/><inertia ixx="9.08e-5" ixy="0" ixz="0" iyy="2.08e-5" iyz="0" izz="9.67e-5"/></inertial>
  </link>
  <joint name="pan_joint" type="revolute"><parent link="base_link"/><child link="head"/>
    <origin xyz="0 0 0.025"/><axis xyz="0 0 1"/><limit lower="-1.2" upper="1.2" effort="2" velocity="10"/></joint>)",
          R"(<servo name="pan" joint="pan_joint" range_deg="160" speed_s_per_60deg="0.2" torque="0.5"/>
    <script><servo t="0" name="pan" pulse_us="1750"/><servo t="1" name="pan" pulse_us="2000"/></script>)");
  Vehicle& v = rig.sim->robot(0);
  const ArticulatedJoint& j = rig.joint("pan_joint");
  const ServoDesc& servo = rig.project.robots[0].servos[0];
  // The script's pulses reach the servo as an MCU's would (Vehicle::command_servo).
  const double target = 0.5 * (80 * kDegToRad);  // 1750 us: half way from centre to the 80 degree end
  double fastest = 0;
  run_for(*rig.sim, 0.05, [&] { fastest = std::max(fastest, std::abs(j.rate())); });
  // The servo's output slews at s = 60 degrees per 0.2 s; the joint's loop (gain k = 20 /s)
  // follows that ramp from rest as s (t - (1 - exp(-k t)) / k): 0.096 rad at 50 ms, below the
  // output's 0.26. 5 mrad: the loop runs on the angle at the start of each 1 ms step.
  const double k = 20, t = 0.05;
  EXPECT_NEAR(j.position(), servo.speed_radps * (t - (1 - std::exp(-k * t)) / k), 0.005);
  run_for(*rig.sim, 0.95, [&] { fastest = std::max(fastest, std::abs(j.rate())); });
  // The joint's loop never asks more than twice the servo's speed to catch up its lag.
  EXPECT_LE(fastest, 2 * servo.speed_radps + 1e-6);
  // SEAR's servo has no dead band: its output reaches the target in 0.13 s, and the joint's
  // loop (20 /s) closes the remaining lag of speed / gain = 0.26 rad to exp(-20 * 0.8) of it.
  EXPECT_NEAR(j.position(), target, 1e-4);
  // Positive is counter-clockwise seen from above, as the URDF's axis z has it: the head's body
  // has turned by the target against the cart.
  const dReal* head = dBodyGetRotation(j.body());
  const dReal* cart = dBodyGetRotation(v.chassis_body());
  const double yaw = std::atan2(head[4], head[0]) - std::atan2(cart[4], cart[0]);
  EXPECT_NEAR(yaw, target, 1e-4);
  // Past the joint's stop the servo's target is held at the stop: 2000 us, from 1 s, asks 80 degrees.
  run_for(*rig.sim, 1.0);
  EXPECT_NEAR(j.position(), 1.2, 1e-3);
}

TEST(UrdfJoint, ServoHoldsALoadWithinTheUrdfsEffort) {
  // The level bob weighs on its joint with m g L = 0.294 N*m. A 1 N*m servo at its centre
  // pulse holds it level; the same servo capped by the URDF's effort of 0.05 N*m cannot, and
  // the bob sinks onto its stop.
  for (const char* effort : {"1", "0.05"}) {
    Rig rig(bob_xml("0 0.15 0", "revolute",
                    fmt::format(R"(<limit lower="-1.0" upper="0.5" effort="{}" velocity="20"/>)", effort)),
            R"(<servo name="shoulder" joint="bob_joint" range_deg="120" torque="1"/>)");
    run_for(*rig.sim, 1.0);
    const double q = rig.joint("bob_joint").position();
    // Held to 1 mrad, finer than a hobby servo resolves (a dead band of 4 us of a 1000 us span
    // over 120 degrees is 8 mrad). SEAR's servo has none; what remains is the joint's motor row
    // giving under load as its CFM lets it (1.5e-8 rad measured).
    if (std::string(effort) == "1") EXPECT_NEAR(q, 0.0, 1e-3);
    else EXPECT_NEAR(q, -1.0, 1e-3);
    EXPECT_NEAR(rig.project.robots[0].servos[0].torque_nm, std::min(1.0, std::stod(effort)), 1e-12);
  }
}

TEST(UrdfJoint, SliderStopsAtItsUpperLimit) {
  // A 0.1 kg block on a prismatic joint whose axis points down: its weight slides it along +axis
  // until the upper stop, 80 mm down.
  Rig rig(R"(
  <link name="block">
    <collision><geometry><box size="0.03 0.03 0.03"/></geometry></collision>
    <inertial><mass value="0.1"/><inertia ixx="1.5e-5" ixy="0" ixz="0" iyy="1.5e-5" iyz="0" izz="1.5e-5"/></inertial>
  </link>
  <joint name="lift_joint" type="prismatic"><parent link="base_link"/><child link="block"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 0 -1"/><limit lower="-0.05" upper="0.08" effort="10" velocity="1"/></joint>)");
  Vehicle& v = rig.sim->robot(0);
  const ArticulatedJoint& j = rig.joint("lift_joint");
  const double start = dBodyGetPosition(j.body())[2] - dBodyGetPosition(v.chassis_body())[2];
  double furthest = 0;
  run_for(*rig.sim, 1.0, [&] { furthest = std::max(furthest, j.position()); });
  // It falls 80 mm in 0.13 s and meets the stop at sqrt(2 g d) = 1.25 m/s: one step's travel past
  // it at most (1.25 mm), then the stop's ERP pulls it back; resting, its weight presses the stop
  // by 1 N * h * CFM / ERP = 5e-9 m.
  EXPECT_LE(furthest, 0.08 + std::sqrt(2 * kG * 0.08) * kStep_s);
  EXPECT_NEAR(j.position(), 0.08, 1e-5);
  const double now = dBodyGetPosition(j.body())[2] - dBodyGetPosition(v.chassis_body())[2];
  EXPECT_NEAR(start - now, 0.08, 1e-4);  // 80 mm lower against the cart, which settled on its tyres meanwhile
}

TEST(UrdfJoint, LinkBelowTheChassisStartsClearOfTheGround) {
  // The ball hangs 0.4 m below its pivot, 0.1 m below base_link, which its wheels would put
  // 45 mm up: the ball would start 75 mm deep in the ground. The robot starts higher instead,
  // the ball's bottom on the ground plus the 2 mm spawn clearance (vehicle.cpp).
  Rig rig(bob_xml("0 0 -0.4", "continuous", ""));
  const double bottom = dBodyGetPosition(rig.joint("bob_joint").body())[2] - 0.02;
  EXPECT_NEAR(bottom, 0.002, 1e-9);
}

TEST(UrdfJoint, ServoOnASliderOrAMissingJointIsRefusedAtItsLine) {
  TempDir dir;
  const std::string urdf = (dir.path() / "rig.urdf").string();
  write_text(urdf, rig_urdf(R"(
  <link name="block"><inertial><mass value="0.1"/><inertia ixx="1.5e-5" ixy="0" ixz="0" iyy="1.5e-5" iyz="0" izz="1.5e-5"/></inertial></link>
  <joint name="lift_joint" type="prismatic"><parent link="base_link"/><child link="block"/>
    <axis xyz="0 0 1"/><limit lower="0" upper="0.1" effort="10" velocity="1"/></joint>)"));
  const std::string project = project_xml("", "", R"(
  <robot name="rig" urdf=")" + urdf + R"(">
    <wheel name="left" joint="left_wheel_joint"/>
    <wheel name="right" joint="right_wheel_joint"/>
    <caster link="front_caster"/>
    <servo name="lift" joint="lift_joint"/>
    <servo name="wrist" joint="lift_jiont"/>
  </robot>)");
  Diagnostics diagnostics;
  EXPECT_FALSE(load_project_text(project, (dir.path() / "p.xml").string(), diagnostics));
  const std::string all = diagnostics.joined();
  const Diagnostic* e = find_error(diagnostics, "servo 'lift' turns joint 'lift_joint', which is prismatic");
  ASSERT_NE(e, nullptr) << all;
  EXPECT_EQ(e->line, line_of(project, "<servo name=\"lift\""));
  e = find_error(diagnostics, "servo 'wrist' turns joint 'lift_jiont', which is not a live joint");
  ASSERT_NE(e, nullptr) << all;
  EXPECT_NE(e->message.find("(did you mean 'lift_joint'?)"), std::string::npos) << all;
}

TEST(UrdfJoint, CheckListsEachLiveJoint) {
  TempDir dir;
  const std::string urdf = (dir.path() / "rig.urdf").string();
  write_text(urdf, rig_urdf(bob_xml("0 0.15 0", "revolute", R"(<limit lower="-1.0" upper="0.5" effort="0.2" velocity="3"/>)",
                                    R"(<dynamics damping="0.01" friction="0.02"/>)")));
  const std::string project = (dir.path() / "p.xml").string();
  write_text(project, project_xml("", "", R"(
  <robot name="rig" urdf=")" + urdf + R"(">
    <wheel name="left" joint="left_wheel_joint"/>
    <wheel name="right" joint="right_wheel_joint"/>
    <caster link="front_caster"/>
    <servo name="arm" joint="bob_joint" torque="0.5" speed_s_per_60deg="0.1"/>
  </robot>)"));
  const CommandOutput out = command_output(std::string(SEAR_BINARY) + " check " + project + " 2>&1");
  ASSERT_EQ(out.exit_code, 0) << out.out;
  // The servo's 0.5 N*m and 10.5 rad/s, capped by the URDF's effort and velocity.
  EXPECT_NE(out.out.find("  joint bob_joint: a live hinge carrying link 'bob' (0.2 kg), turned by servo 'arm' (0.2 N*m, "
                         "3 rad/s), stops -1..0.5 rad, damping 0.01 N*m*s/rad, friction 0.02 N*m"),
            std::string::npos)
      << out.out;
}

TEST(UrdfJoint, TraceCarriesEachLiveJointsPositionTheSameEachRun) {
  TempDir dir;
  const std::string urdf = (dir.path() / "rig.urdf").string();
  write_text(urdf, rig_urdf(bob_xml("0 0.15 0", "revolute", R"(<limit lower="-1.0" upper="0.5" effort="1" velocity="20"/>)")));
  const std::string project = project_xml(R"(step="0.001")", "", R"(
  <run duration="1" seed="1" trace_rate="10"/>
  <robot name="rig" urdf=")" + urdf + R"(">
    <wheel name="left" joint="left_wheel_joint"/>
    <wheel name="right" joint="right_wheel_joint"/>
    <caster link="front_caster"/>
  </robot>)");
  TempDir first_dir, second_dir;
  const SearRun first = run_sear(first_dir, project, "--quiet");
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const std::vector<std::string> rows = lines_of(first.file("trace_rig.csv"));
  ASSERT_GE(rows.size(), 2u);
  const std::string& header = rows.front();
  const std::string column = ",joint_bob_joint_pos";
  ASSERT_GE(header.size(), column.size());
  EXPECT_EQ(header.substr(header.size() - column.size()), column) << header;
  // On its stop at the end (PassiveHingeFallsOntoItsStopAndStaysThere), printed to 1e-6.
  const std::string& last = rows.back();
  EXPECT_NEAR(std::stod(last.substr(last.rfind(',') + 1)), -1.0, 1e-4) << last;
  const SearRun second = run_sear(second_dir, project, "--quiet");
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(first.file("trace_rig.csv"), second.file("trace_rig.csv"));
}

}  // namespace
}  // namespace sear::test
