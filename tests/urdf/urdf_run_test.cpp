// An imported URDF robot in the simulation: its wheels roll (v = omega r), its motors reach the
// speed of their model, its devices sit on their links, `sear check` prints its meshes' extents,
// and the avoider firmware drives it through the avoider's scenario.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "../command_output.hpp"
#include "../temp_dir.hpp"
#include "../test_world.hpp"
#include "scene/project_loader.hpp"
#include "urdf_files.hpp"

namespace sear::test {
namespace {

const std::string kAssets = SEAR_ASSET_DIR;

// The diffbot of assets/robots/diffbot.urdf with the rover's gearmotors, on flat ground.
std::string diffbot_project(const std::string& extra = "") {
  return project_xml(R"(step="0.001")", "", R"(
  <robot name="diffbot" urdf="../robots/diffbot.urdf">
    <package name="diffbot" dir=".."/>
    <chassis material="plastic"/>
    <wheel name="left" joint="left_wheel_joint" material="rubber"/>
    <wheel name="right" joint="right_wheel_joint" material="rubber"/>
    <caster link="caster_link"/>
    <motor name="left" wheels="left" stall_torque="0.6" no_load_rpm="160" gear_friction="0.02"/>
    <motor name="right" wheels="right" stall_torque="0.6" no_load_rpm="160" gear_friction="0.02"/>
    )" + extra + R"(
  </robot>)");
}

TEST(UrdfRun, ImportedWheelsRollAtOmegaTimesRadius) {
  const ProjectDesc project = project_from_xml(diffbot_project());
  Simulation sim(project, 1);
  const RobotDesc& robot = project.robots[0];
  ASSERT_EQ(robot.wheels.size(), 2u);
  const double r = robot.wheels[0].radius_m;
  EXPECT_NEAR(r, 0.045, 1e-6);  // the wheel STL's rim, 45 mm at scale 0.001 (float vertices)
  const MotorDesc& motor = robot.motors[0];
  for (double duty : {0.5, 1.0}) {
    drive(sim, "left", duty, MotorDirection::Forward);
    drive(sim, "right", duty, MotorDirection::Forward);
    run_for(sim, 3.0);
    const VehicleState s = sim.robot(0).state();
    const double omega = 0.5 * (sim.robot(0).wheel_speed(0) + sim.robot(0).wheel_speed(1));
    // Rolling without slip: ODE's friction rows carry no slip term, so a tyre slides only once
    // traction would exceed mu N, and at a steady speed it pushes against the gearbox friction
    // alone. What is left is the contacts' give (ERP 0.4, CFM 1e-5 at 1 ms: 4e7 N/m, 0.2 um
    // under 7.5 N per wheel) and the step's discretisation: 0.2 % of the speed covers both.
    EXPECT_NEAR(s.forward_speed_mps, omega * r, 0.002 * omega * r) << "duty " << duty;
    // The torque line meets the gear friction: omega = omega_free (duty - friction / stall);
    // 5 % as for the hand-written rover (drive_test), for the rolling resistance of the contacts.
    const double expected = motor.no_load_speed_radps * (duty - motor.gear_friction_nm / motor.stall_torque_nm);
    EXPECT_NEAR(omega, expected, 0.05 * expected) << "duty " << duty;
    EXPECT_LT(std::abs(s.position_m.y()), 0.01);  // straight ahead
  }
}

TEST(UrdfRun, ImportedRobotRestsOnItsWheelsAndCaster) {
  // The direct solver (the default) holds a resting robot still, where the iterative one at its
  // default 20 sweeps lets it creep (resting_rover_test).
  const ProjectDesc project = project_from_xml(diffbot_project());
  const RobotDesc& robot = project.robots[0];
  Simulation sim(project, 1);
  // It drops its 2 mm of spawn clearance in 20 ms (sqrt(2 h / g)) and has settled well before 0.2 s.
  run_for(sim, 0.2);
  Vehicle& v = sim.robot(0);
  // Both axles 45 mm up, the caster ball's bottom on the ground, base_link's origin (midway
  // between the wheel centres) 45 mm up: the URDF's geometry, placed about the centre of mass.
  // 0.5 mm: ODE's contact surface layer (0.5 mm, physics_world) lets a resting body sink that
  // deep before its contacts push back; the contacts' own give is 0.2 um (ERP 0.4, CFM 1e-5 at
  // 1 ms: 4e7 N/m under 7.5 N).
  for (std::size_t w = 0; w < 2; ++w) EXPECT_NEAR(dBodyGetPosition(v.wheel_body(w))[2], 0.045, 5e-4) << w;
  dVector3 p;
  const Eigen::Vector3d ball = robot.casters[0].position_m - Eigen::Vector3d(0, 0, robot.casters[0].radius_m);
  dBodyGetRelPointPos(v.chassis_body(), ball.x(), ball.y(), ball.z(), p);
  EXPECT_NEAR(p[2], 0.0, 5e-4);
  const Eigen::Vector3d base = robot.urdf.base_origin_m;
  dBodyGetRelPointPos(v.chassis_body(), base.x(), base.y(), base.z(), p);
  EXPECT_NEAR(p[2], 0.045, 5e-4);
  // The pose places the chassis origin, the centre of mass; base_link is 41 mm ahead of it.
  EXPECT_NEAR(p[0], base.x(), 1e-4);
  EXPECT_NEAR(v.state().position_m.x(), 0.0, 1e-4);
  EXPECT_LT(v.state().velocity_mps.norm(), 1e-3);
}

TEST(UrdfRun, DevicesSitOnTheirLinks) {
  Diagnostics diagnostics;
  const auto project = load_project(kAssets + "/projects/avoider_urdf.xml", diagnostics);
  ASSERT_TRUE(project) << diagnostics.joined();
  const RobotDesc& robot = project->robots[0];
  const Eigen::Vector3d base = robot.urdf.base_origin_m;
  const auto device = [&](const std::string& name) -> const DeviceDesc& {
    for (const auto& d : robot.mcus[0].devices)
      if (d.name == name) return d;
    throw std::runtime_error("no device " + name);
  };
  // ir_left_joint: xyz 0.11 0.06 0.03, yaw 30 degrees.
  EXPECT_TRUE((device("ir_left").position_m - base).isApprox(Eigen::Vector3d(0.11, 0.06, 0.03), 1e-12));
  EXPECT_NEAR(device("ir_left").yaw_rad, M_PI / 6, 1e-12);
  EXPECT_NEAR(device("ir_right").yaw_rad, -M_PI / 6, 1e-12);
  EXPECT_TRUE((device("bumper").position_m - base).isApprox(Eigen::Vector3d(0.10, 0, 0), 1e-12));
  // The lumped centre of mass: the 1.5 kg chassis at (-0.04, 0, 0.01) and the 0.02 kg caster
  // ball at (-0.15, 0, -0.025) under base_link.
  EXPECT_TRUE((-base).isApprox(Eigen::Vector3d((1.5 * -0.04 + 0.02 * -0.15) / 1.52, 0, (1.5 * 0.01 + 0.02 * -0.025) / 1.52),
                               1e-12))
      << base.transpose();
}

TEST(UrdfRun, MountErrorsNameTheirLine) {
  const std::string xml = diffbot_project(R"(<mcu name="main">
      <firmware sources="../../firmware_examples/avoider/avoider.c"/>
      <gp2d12 name="ir" adc="0"/>
    </mcu>
    <mount device="ir" link="ir_lef_link"/>
    <mount device="nothing" link="ir_left_link"/>)");
  Diagnostics diagnostics;
  EXPECT_FALSE(load_project_text(xml, kAssets + "/projects/inline.xml", diagnostics));
  const std::string all = diagnostics.joined();
  EXPECT_NE(all.find("<mount> names link 'ir_lef_link', which the URDF does not have (did you mean 'ir_left_link'?)"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("<mount> names unknown device 'nothing'"), std::string::npos) << all;
}

TEST(UrdfRun, CheckPrintsEachMeshExtentInMetres) {
  const CommandOutput out = command_output(std::string(SEAR_BINARY) + " check " + kAssets +
                                           "/projects/avoider_urdf.xml 2>&1");
  ASSERT_EQ(out.exit_code, 0) << out.out;
  // The chassis STL in mm at scale 0.001 and the rangers' COLLADA in mm by its <unit>.
  EXPECT_NE(out.out.find("base_link visual package://diffbot/meshes/diffbot/chassis.stl: 0.3 x 0.18 x 0.06 m"),
            std::string::npos)
      << out.out;
  EXPECT_NE(out.out.find("ir_left_link visual package://diffbot/meshes/diffbot/ranger.dae: 0.013 x 0.04 x 0.014 m"),
            std::string::npos)
      << out.out;
  EXPECT_NE(out.out.find("left_wheel collision package://diffbot/meshes/diffbot/wheel.stl: 0.09 x 0.025 x 0.09 m"),
            std::string::npos)
      << out.out;
}

// A ball caster's link: a sphere of `radius` whose centre is `z` below base_link, `x` ahead of it.
std::string caster_xml(double x, double z, double radius = 0.01) {
  return fmt::format(R"(
  <link name="caster">
    <collision><geometry><sphere radius="{2}"/></geometry></collision>
  </link>
  <joint name="caster_joint" type="fixed">
    <parent link="base_link"/><child link="caster"/><origin xyz="{0} 0 {1}"/>
  </joint>)",
                     x, -z, radius);
}

// A small robot whose URDF draws two import warnings: an rpy written short of pi/2 (snapped), and a
// fixed skid box down on the ground the wheels stand on (it drags).
const std::string kWarnedUrdf = R"(<?xml version="1.0"?>
<robot name="warned">
  <link name="base_link">
    <collision><geometry><box size="0.2 0.12 0.04"/></geometry></collision>
    <inertial><mass value="1.0"/><inertia ixx="0.0015" ixy="0" ixz="0" iyy="0.0035" iyz="0" izz="0.0045"/></inertial>
  </link>
  <link name="skid">
    <collision><origin rpy="0 0 1.5708"/><geometry><box size="0.02 0.02 0.03"/></geometry></collision>
  </link>
  <joint name="skid_joint" type="fixed">
    <parent link="base_link"/><child link="skid"/><origin xyz="-0.08 0 -0.03"/>
  </joint>)" + wheel_xml("left", 0.08) + wheel_xml("right", -0.08) + caster_xml(0.08, 0.035) + R"(
</robot>
)";

std::string warned_project() {
  return project_xml("", "", R"(
  <robot name="warned" urdf="robot.urdf">
    <wheel name="left" joint="left_wheel_joint" material="rubber"/>
    <wheel name="right" joint="right_wheel_joint" material="rubber"/>
    <caster link="caster"/>
  </robot>)");
}

// `sear run` prints the import's warnings once, before the run, as `sear check` does, and keeps
// them in the summary.
TEST(UrdfRun, RunPrintsTheImportWarningsOnceAndKeepsThemInTheSummary) {
  TempDir dir;
  write_text(dir.path() / "robot.urdf", kWarnedUrdf);
  write_text(dir.path() / "project.xml", warned_project());
  const std::string urdf = (dir.path() / "robot.urdf").string();
  const std::string snapped = fmt::format("{}:{}: warning: rpy=\"0 0 1.5708\" is within", urdf,
                                          line_of(kWarnedUrdf, "rpy=\"0 0 1.5708\""));
  const std::string drags = fmt::format("{}:{}: warning: link 'skid': its collision shape reaches down to the ground",
                                        urdf, line_of(kWarnedUrdf, "<collision><origin rpy=\"0 0 1.5708\""));
  const auto out = dir.path() / "run";
  // stderr alone (stdout, the summary, to /dev/null): the warnings go where errors go.
  const CommandOutput run = command_output(std::string(SEAR_BINARY) + " run " + (dir.path() / "project.xml").string() +
                                           " -d 0.05 --no-plots -o " + out.string() + " 2>&1 >/dev/null");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  for (const std::string& warning : {snapped, drags}) {
    const auto first = run.out.find(warning);
    EXPECT_NE(first, std::string::npos) << warning << "\n" << run.out;
    EXPECT_EQ(run.out.find(warning, first + 1), std::string::npos) << "printed twice: " << warning << "\n" << run.out;
  }
  const CommandOutput check =
      command_output(std::string(SEAR_BINARY) + " check " + (dir.path() / "project.xml").string() + " 2>&1 >/dev/null");
  ASSERT_EQ(check.exit_code, 0) << check.out;
  EXPECT_NE(check.out.find(snapped), std::string::npos) << check.out;
  EXPECT_NE(check.out.find(drags), std::string::npos) << check.out;

  std::ifstream in(out / "summary.json");
  const auto summary = nlohmann::json::parse(in);
  ASSERT_EQ(summary["import_warnings"].size(), 2u) << summary["import_warnings"].dump(2);
  EXPECT_EQ(summary["import_warnings"][0]["file"], urdf);
  EXPECT_EQ(summary["import_warnings"][0]["line"], line_of(kWarnedUrdf, "rpy=\"0 0 1.5708\""));
  EXPECT_NE(summary["import_warnings"][1]["text"].get<std::string>().find("will slide over the floor"), std::string::npos);
  std::ifstream text_in(out / "summary.txt");
  const std::string text(std::istreambuf_iterator<char>(text_in), {});
  EXPECT_NE(text.find(fmt::format("  import warning: {}:{}: rpy=", urdf, line_of(kWarnedUrdf, "rpy=\"0 0 1.5708\""))),
            std::string::npos)
      << text;
}

// A robot whose body mesh is in package 'foo' and whose name takes ${namespace}, as a launch file
// would fill them in: the project says neither, the command line does.
const std::string kPackagedUrdf = R"(<?xml version="1.0"?>
<robot name="${namespace}bot">
  <link name="base_link">
    <visual><geometry><mesh filename="package://foo/meshes/body.stl"/></geometry></visual>
    <collision><geometry><box size="0.2 0.12 0.04"/></geometry></collision>
    <inertial><mass value="1.0"/><inertia ixx="0.0015" ixy="0" ixz="0" iyy="0.0035" iyz="0" izz="0.0045"/></inertial>
  </link>)" + wheel_xml("left", 0.08) + wheel_xml("right", -0.08) + caster_xml(-0.08, 0.035) + R"(
</robot>
)";

TEST(UrdfRun, PackageAndArgOnTheCommandLineFillWhatTheProjectLeavesOut) {
  TempDir dir;
  write_text(dir.path() / "robot.urdf", kPackagedUrdf);
  write_text(dir.path() / "pkg/meshes/body.stl", box_stl(0.2, 0.12, 0.04));
  write_text(dir.path() / "project.xml", project_xml("", "", R"(
  <robot urdf="robot.urdf">
    <wheel name="left" joint="left_wheel_joint" material="rubber"/>
    <wheel name="right" joint="right_wheel_joint" material="rubber"/>
    <caster link="caster"/>
  </robot>)"));
  const std::string urdf = (dir.path() / "robot.urdf").string();
  const std::string project = (dir.path() / "project.xml").string();
  const std::string pkg = (dir.path() / "pkg").string();
  const auto sear = [&](const std::string& args) { return command_output(std::string(SEAR_BINARY) + " " + args + " 2>&1"); };

  // Neither given: the unexpanded name is refused at its line, naming --arg.
  CommandOutput out = sear("check " + project);
  EXPECT_EQ(out.exit_code, 1) << out.out;
  EXPECT_NE(out.out.find(urdf + ":2: error: unexpanded xacro expression '${namespace}'"), std::string::npos) << out.out;
  EXPECT_NE(out.out.find("--arg NAME=VALUE"), std::string::npos) << out.out;
  // The name given, the package not: the mesh is refused at its line, naming --package.
  out = sear("check " + project + " --arg namespace=my_");
  EXPECT_EQ(out.exit_code, 1) << out.out;
  EXPECT_NE(out.out.find(urdf + ":4: error: link 'base_link': mesh 'package://foo/meshes/body.stl' is in package 'foo', "
                                "which is not known"),
            std::string::npos)
      << out.out;
  EXPECT_NE(out.out.find("--package foo=DIR"), std::string::npos) << out.out;
  // Both: the robot is named from the argument, its mesh found in the folder.
  out = sear("check " + project + " --arg namespace=my_ --package foo=" + pkg);
  EXPECT_EQ(out.exit_code, 0) << out.out;
  EXPECT_NE(out.out.find("robot 'my_bot' from " + urdf), std::string::npos) << out.out;
  EXPECT_NE(out.out.find("base_link visual package://foo/meshes/body.stl: 0.2 x 0.12 x 0.04 m"), std::string::npos)
      << out.out;
  // The command line wins over the project's own <arg> and <package>.
  std::string xml = project_xml("", "", R"(
  <robot urdf="robot.urdf">
    <arg name="namespace" value="project_"/>
    <package name="foo" dir="nowhere"/>
    <wheel name="left" joint="left_wheel_joint" material="rubber"/>
    <wheel name="right" joint="right_wheel_joint" material="rubber"/>
    <caster link="caster"/>
  </robot>)");
  write_text(dir.path() / "own.xml", xml);
  out = sear("check " + (dir.path() / "own.xml").string());
  EXPECT_EQ(out.exit_code, 1) << out.out;  // its own package folder holds no mesh
  out = sear("check " + (dir.path() / "own.xml").string() + " --arg namespace=my_ --package foo=" + pkg);
  EXPECT_EQ(out.exit_code, 0) << out.out;
  EXPECT_NE(out.out.find("robot 'my_bot' from " + urdf), std::string::npos) << out.out;
  // `sear run` takes them alike (a run of 10 ms).
  out = sear("run " + project + " -d 0.01 --no-plots -q -o " + (dir.path() / "run").string() +
             " --arg namespace=my_ --package foo=" + pkg);
  EXPECT_EQ(out.exit_code, 0) << out.out;
  {
    std::ifstream in(dir.path() / "run/summary.json");
    EXPECT_EQ(nlohmann::json::parse(in)["robots"][0]["name"], "my_bot");
  }

  // `sear test` passes them on to each run (which works in the suite's folder: the package folder
  // given relative to here still resolves); the expectation names the robot by its argument.
  std::string suite = project_xml("", "", R"(
  <robot urdf="../robot.urdf">
    <wheel name="left" joint="left_wheel_joint" material="rubber"/>
    <wheel name="right" joint="right_wheel_joint" material="rubber"/>
    <caster link="caster"/>
  </robot>)");
  suite.replace(suite.rfind("</project>"), 10, R"(<expect><no_collision robot="my_bot"/></expect></project>)");
  write_text(dir.path() / "suite/project.xml", suite);
  const std::string test = "test " + (dir.path() / "suite").string() + " --timeout 0.05 -o " +
                           (dir.path() / "test-out").string();
  out = command_output("cd " + dir.path().string() + " && " + SEAR_BINARY + " " + test +
                       " --arg namespace=my_ --package foo=pkg 2>&1");
  EXPECT_EQ(out.exit_code, 0) << out.out;
  EXPECT_NE(out.out.find("1 of 1 case passed"), std::string::npos) << out.out;
  out = sear(test + " --arg namespace=my_");  // no package: the run fails, and says why
  EXPECT_NE(out.exit_code, 0) << out.out;
  EXPECT_NE(out.out.find("in package 'foo', which is not known"), std::string::npos) << out.out;
  EXPECT_NE(out.out.find("--timeout 0.05 --arg namespace=my_\n"), std::string::npos) << out.out;  // reproduce:

  // Malformed values are refused by the option's name, before anything is loaded.
  const std::pair<std::string, std::string> bad[] = {
      {"--package foo", "--package: expected NAME=DIR, got 'foo' (no '=')"},
      {"--package =" + pkg, "--package: expected NAME=DIR, got '=" + pkg + "' (the name is empty)"},
      {"--package foo=" + pkg + "/nowhere", "--package: foo=" + pkg + "/nowhere: '" + pkg + "/nowhere' does not exist"},
      {"--package foo=" + pkg + "/meshes/body.stl", "--package: foo=" + pkg + "/meshes/body.stl: '" + pkg +
                                                        "/meshes/body.stl' is not a folder"},
      {"--package foo=", "--package: foo=: no folder after '='"},
      {"--arg namespace", "--arg: expected NAME=VALUE, got 'namespace' (no '=')"},
      {"--arg =x", "--arg: expected NAME=VALUE, got '=x' (the name is empty)"},
  };
  for (const auto& [args, message] : bad)
    for (const char* command : {"check ", "run "}) {
      out = sear(command + project + " " + args);
      EXPECT_NE(out.exit_code, 0) << command << args;
      EXPECT_NE(out.out.find(message), std::string::npos) << command << args << "\n" << out.out;
    }
}

// A two-wheeled robot whose rear rests on a skid: an octahedron (corners 30 mm from its centre)
// turned 45 degrees about x, 150 mm behind the axle. Its hull's lowest edge lies r / sqrt(2) =
// 21.2 mm below its centre, placed to touch the ground the wheels stand on with the chassis level;
// its bounding box, turned the same way, reaches r sqrt(2) = 42.4 mm below it, 21.2 mm lower.
const double kSkidR = 0.03;
const std::string kSkidUrdf = fmt::format(R"(<?xml version="1.0"?>
<robot name="skidder">
  <link name="base_link">
    <collision><geometry><box size="0.2 0.12 0.04"/></geometry></collision>
    <inertial><origin xyz="-0.04 0 0"/><mass value="1.0"/>
      <inertia ixx="0.00133" ixy="0" ixz="0" iyy="0.00347" iyz="0" izz="0.00453"/></inertial>
  </link>
  <link name="skid">
    <collision><origin rpy="0.7853981633974483 0 0"/><geometry><mesh filename="octahedron.stl"/></geometry></collision>
  </link>
  <joint name="skid_joint" type="fixed">
    <parent link="base_link"/><child link="skid"/><origin xyz="-0.15 0 {:.9f}"/>
  </joint>)", -0.045 + kSkidR / std::sqrt(2.0)) + wheel_xml("left", 0.08) + wheel_xml("right", -0.08) +
                                  caster_xml(0.0, -0.1) + R"(
</robot>
)";

struct Rest {
  double pitch_rad = 0;   // the chassis's nose down, positive
  double lowest_m = 0;    // the skid's lowest point above the ground
  double predicted_rad = 0;
};

// The robot settled with its skid's collision `replace`d: its pitch, and the one predicted from the
// skid's shape as imported (the pitch about the axle that puts its lowest point on the ground).
Rest settle_on_skid(const std::string& replace) {
  TempDir dir;
  write_text(dir.path() / "octahedron.stl", octahedron_stl(kSkidR));
  write_text(dir.path() / "robot.urdf", kSkidUrdf);
  const ProjectDesc project = project_from_xml(project_xml(R"(step="0.001")", "", R"(
  <robot name="skidder" urdf=")" + (dir.path() / "robot.urdf").string() + R"(">
    <wheel name="left" joint="left_wheel_joint" material="rubber"/>
    <wheel name="right" joint="right_wheel_joint" material="rubber"/>
    <caster link="caster"/>  <!-- a differential robot needs one: this one is up in the air, 10 cm above base_link -->
    <collision link="skid" max_triangles="4" replace=")" + replace + R"("/>
    <motor name="left" wheels="left" stall_torque="0.6" no_load_rpm="160" gear_friction="0.02"/>
    <motor name="right" wheels="right" stall_torque="0.6" no_load_rpm="160" gear_friction="0.02"/>
  </robot>)"));
  const RobotDesc& robot = project.robots[0];
  EXPECT_EQ(robot.chassis.parts.size(), 2u);
  const ShapeDesc& skid = robot.chassis.parts.back();
  // Its points in the chassis frame: the hull's corners, or the box's.
  std::vector<Eigen::Vector3d> points;
  if (skid.kind == ShapeDesc::Kind::Mesh)
    for (const auto& v : skid.mesh.vertices) points.push_back(skid.position_m + skid.rotation * v.cast<double>());
  else
    for (int k = 0; k < 8; ++k)
      points.push_back(skid.position_m + skid.rotation * (0.5 * Eigen::Vector3d(k & 1 ? 1 : -1, k & 2 ? 1 : -1,
                                                                                k & 4 ? 1 : -1))
                                                             .cwiseProduct(skid.size_m));
  // Turned by theta about the axle (nose down), a point q from the axle is at -q.x sin + q.z cos
  // below it; the lowest must reach the wheels' radius. Bisection: the height rises with theta.
  const Eigen::Vector3d axle = robot.wheels[0].position_m;
  const double radius = robot.wheels[0].radius_m;
  const auto lowest_at = [&](double theta) {
    double lowest = 1e9;
    for (const auto& p : points)
      lowest = std::min(lowest, -(p.x() - axle.x()) * std::sin(theta) + (p.z() - axle.z()) * std::cos(theta));
    return lowest + radius;
  };
  Rest rest;
  double lo = -0.3, hi = 0.5;
  for (int k = 0; k < 60; ++k) (lowest_at(0.5 * (lo + hi)) < 0 ? lo : hi) = 0.5 * (lo + hi);
  rest.predicted_rad = 0.5 * (lo + hi);

  Simulation sim(project, 1);
  run_for(sim, 1.0);
  Vehicle& v = sim.robot(0);
  const dReal* r = dBodyGetRotation(v.chassis_body());
  rest.pitch_rad = std::asin(-r[8]);  // the chassis x axis's height: -sin(pitch)
  rest.lowest_m = 1e9;
  for (const auto& p : points) {
    dVector3 w;
    dBodyGetRelPointPos(v.chassis_body(), p.x(), p.y(), p.z(), w);
    rest.lowest_m = std::min(rest.lowest_m, static_cast<double>(w[2]));
  }
  EXPECT_LT(v.state().velocity_mps.norm(), 1e-3);
  return rest;
}

// The skid's hull is what touches the ground: the chassis rests level on it, where its bounding
// box would tip the nose down by 8 degrees.
TEST(UrdfRun, AHullSkidRestsWhereItsHullSaysAndABoxSkidWhereItsBoxSays) {
  const Rest hull = settle_on_skid("hull");
  const Rest box = settle_on_skid("box");
  // The hull's lowest edge was placed level with the wheels' bottoms.
  EXPECT_NEAR(hull.predicted_rad, 0.0, 1e-6);
  // The box's reaches 21.2 mm lower, 150 mm behind the axle: about asin(0.0212 / 0.15), turned.
  EXPECT_GT(box.predicted_rad, 0.12);
  // ODE's contacts let a resting body sink up to its surface layer, 0.5 mm (physics_world; the
  // contacts' own give under 10 N is 0.2 um): the skid's lowest point lies within 0.5 mm of the
  // ground, and the pitch within 0.5 mm over the 150 mm from the axle, 3.3e-3 rad, of the prediction.
  for (const Rest& rest : {hull, box}) {
    EXPECT_NEAR(rest.lowest_m, 0.0, 5e-4);
    EXPECT_NEAR(rest.pitch_rad, rest.predicted_rad, 5e-4 / 0.15);
  }
  EXPECT_GT(box.pitch_rad - hull.pitch_rad, 0.1);
}

// The avoider, unmodified, drives the imported robot through the avoider's own scenario.
TEST(UrdfRun, AvoiderDrivesTheImportedRobotThroughItsScenario) {
  TempDir dir;
  const auto out = dir.path() / "run";
  const CommandOutput run = command_output(std::string(SEAR_BINARY) + " run " + kAssets +
                                           "/projects/avoider_urdf.xml --quiet -o " + out.string() + " 2>&1");
  const std::string summary_text = [&] {
    std::ifstream in(out / "summary.json");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  ASSERT_EQ(run.exit_code, 0) << run.out << summary_text;
  const auto summary = nlohmann::json::parse(summary_text);
  ASSERT_EQ(summary["expectations"].size(), 6u);
  for (const auto& e : summary["expectations"]) EXPECT_EQ(e["verdict"], "passed") << e.dump();
}

}  // namespace
}  // namespace sear::test
