// Importing hand-made URDFs: lumped mass properties against a hand computation, mesh units (an
// STL in millimetres with its scale, a COLLADA with its <unit>), wheels and casters from their
// shapes, and each pitfall of issue 24 giving its result or its error at its line.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "../command_output.hpp"
#include "../temp_dir.hpp"
#include "scene/convex_hull.hpp"
#include "scene/mesh_loader.hpp"
#include "urdf_files.hpp"

namespace sear::test {
namespace {

// base_link: 2 kg at its origin. battery: 1 kg, fixed 0.1 m ahead and 0.05 m up, turned 90
// degrees about z, its own centre 0.02 m along its x (so along the base's y).
const char* kLumpUrdf = R"(<?xml version="1.0"?>
<robot name="lump">
  <link name="base_link">
    <collision><geometry><box size="0.2 0.1 0.05"/></geometry></collision>
    <inertial><mass value="2.0"/><inertia ixx="0.002" ixy="0" ixz="0" iyy="0.007" iyz="0" izz="0.008"/></inertial>
  </link>
  <link name="battery">
    <collision><geometry><box size="0.1 0.06 0.04"/></geometry></collision>
    <inertial><origin xyz="0.02 0 0"/><mass value="1.0"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.0025"/></inertial>
  </link>
  <joint name="battery_joint" type="fixed">
    <parent link="base_link"/><child link="battery"/>
    <origin xyz="0.1 0 0.05" rpy="0 0 1.5707963267948966"/>
  </joint>
</robot>
)";

TEST(UrdfImport, FixedLinksLumpIntoOneBodyAsAHandComputationHasIt) {
  TempDir dir;
  const Imported in = import_text(dir.path(), kLumpUrdf);
  ASSERT_TRUE(in.ok) << in.diagnostics.joined();
  const ChassisDesc& c = in.robot.chassis;
  // M = 2 + 1. The battery's centre: its link at (0.1, 0, 0.05), its own (0.02, 0, 0) turned
  // 90 degrees about z onto (0, 0.02, 0): (0.1, 0.02, 0.05). C = 1/3 of that.
  EXPECT_DOUBLE_EQ(c.mass_kg, 3.0);
  const Eigen::Vector3d com(0.1 / 3, 0.02 / 3, 0.05 / 3);
  // The chassis origin is the centre of mass: base_link's origin lies at -C in it.
  EXPECT_TRUE(in.robot.report.base_origin_m.isApprox(-com, 1e-12)) << in.robot.report.base_origin_m.transpose();
  // Turning the battery by 90 degrees about z swaps its x and y moments: diag(0.002, 0.001, 0.0025).
  // Parallel axes for two masses at r = (0.1, 0.02, 0.05) apart add the reduced mass
  // mu = 2 * 1 / 3 times (|r|^2 E - r r^T), |r|^2 = 0.0129:
  //   mu * [[0.0029, -0.002, -0.005], [-0.002, 0.0125, -0.001], [-0.005, -0.001, 0.0104]].
  const double mu = 2.0 / 3.0;
  Eigen::Matrix3d expected;
  expected << 0.002 + 0.002 + mu * 0.0029, -mu * 0.002, -mu * 0.005,  //
      -mu * 0.002, 0.007 + 0.001 + mu * 0.0125, -mu * 0.001,          //
      -mu * 0.005, -mu * 0.001, 0.008 + 0.0025 + mu * 0.0104;
  // Sums of a few products of doubles: exact to a few ulps of 0.02 kg*m^2.
  EXPECT_TRUE(c.inertia_kgm2.isApprox(expected, 1e-12)) << c.inertia_kgm2 << "\nexpected\n" << expected;
  EXPECT_NEAR(c.inertia_kgm2(0, 0), 0.00593333333333333, 1e-15);
  // Both boxes are collision parts of the chassis, placed about the centre of mass.
  ASSERT_EQ(c.parts.size(), 2u);
  EXPECT_EQ(c.shape, ChassisDesc::Shape::Parts);
  EXPECT_TRUE(c.parts[1].position_m.isApprox(Eigen::Vector3d(0.1, 0, 0.05) - com, 1e-12));
  EXPECT_TRUE(c.parts[1].rotation.isApprox(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                                           1e-12));
}

// urdfdom's own command-line reader accepts what we import, and sees the same tree.
TEST(UrdfImport, CheckUrdfAcceptsTheExampleRobotWithTheLinksWeImport) {
  const std::string urdf = std::string(SEAR_ASSET_DIR) + "/robots/diffbot.urdf";
  const CommandOutput out = command_output("check_urdf " + urdf + " 2>&1");
  ASSERT_EQ(out.exit_code, 0) << out.out;
  EXPECT_NE(out.out.find("root Link: base_link has 7 child(ren)"), std::string::npos) << out.out;
  UrdfMapping mapping;
  mapping.packages["diffbot"] = SEAR_ASSET_DIR;
  mapping.wheels = {{{}, "left", "left_wheel_joint"}, {{}, "right", "right_wheel_joint"}};
  mapping.casters = {{{}, "caster_link", 0}};
  UrdfRobot robot;
  Diagnostics diagnostics;
  ASSERT_TRUE(import_urdf(urdf, mapping, diagnostics, robot)) << diagnostics.joined();
  EXPECT_EQ(robot.links.size(), 8u);  // base_link and its 7 children
  for (const char* link : {"base_link", "left_wheel", "right_wheel", "caster_link", "ir_left_link", "ir_right_link",
                           "ir_front_link", "bumper_link"})
    EXPECT_TRUE(robot.links.count(link)) << link << " in check_urdf's tree, not in ours";
  EXPECT_TRUE(robot.report.warnings.empty()) << robot.report.warnings[0].second;
}

TEST(UrdfImport, StlInMillimetresTakesItsScale) {
  TempDir dir;
  write_text(dir.path() / "meshes/body.stl", box_stl(200, 100, 50));
  const std::string urdf = R"(<robot name="mm">
  <link name="base_link">
    <collision><geometry><mesh filename="meshes/body.stl" scale="0.001 0.001 0.001"/></geometry></collision>
    <inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.0035" iyz="0" izz="0.004"/></inertial>
  </link>
</robot>)";
  const Imported in = import_text(dir.path(), urdf);
  ASSERT_TRUE(in.ok) << in.diagnostics.joined();
  ASSERT_EQ(in.robot.report.meshes.size(), 1u);
  const auto& mesh = in.robot.report.meshes[0];
  // 200 x 100 x 50 mm; vertices are floats, good to 1e-7 of 0.2 m.
  EXPECT_TRUE(mesh.extent_m.isApprox(Eigen::Vector3d(0.2, 0.1, 0.05), 1e-6)) << mesh.extent_m.transpose();
  EXPECT_EQ(mesh.triangles, 12u);
  EXPECT_EQ(mesh.use, "collision");
  ASSERT_EQ(in.robot.chassis.parts.size(), 1u);
  EXPECT_EQ(in.robot.chassis.parts[0].kind, ShapeDesc::Kind::Mesh);
  EXPECT_NEAR(in.robot.chassis.size_m.x(), 0.2, 1e-6);
  EXPECT_NEAR(in.robot.chassis.bottom_z_m, -0.025, 1e-6);
}

TEST(UrdfImport, ColladaUnitReachesTheVertices) {
  TempDir dir;
  write_text(dir.path() / "body.dae", box_dae(200, 100, 50, 0.001));
  write_text(dir.path() / "inch.dae", box_dae(2, 1, 0.5, 0.0254));
  const std::string urdf = R"(<robot name="dae">
  <link name="base_link">
    <visual><geometry><mesh filename="body.dae"/></geometry></visual>
    <visual><geometry><mesh filename="inch.dae"/></geometry></visual>
    <inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.0035" iyz="0" izz="0.004"/></inertial>
  </link>
</robot>)";
  const Imported in = import_text(dir.path(), urdf);
  ASSERT_TRUE(in.ok) << in.diagnostics.joined();
  ASSERT_EQ(in.robot.report.meshes.size(), 2u);
  EXPECT_TRUE(in.robot.report.meshes[0].extent_m.isApprox(Eigen::Vector3d(0.2, 0.1, 0.05), 1e-6))
      << in.robot.report.meshes[0].extent_m.transpose();
  // 2 x 1 x 0.5 inches of 25.4 mm.
  EXPECT_TRUE(in.robot.report.meshes[1].extent_m.isApprox(Eigen::Vector3d(0.0508, 0.0254, 0.0127), 1e-6))
      << in.robot.report.meshes[1].extent_m.transpose();
  EXPECT_EQ(in.robot.report.visuals.size(), 2u);
}

std::string diff_drive(const std::string& wheel_inertial_left, const std::string& caster_joint = "fixed") {
  return R"(<?xml version="1.0"?>
<robot name="dd">
  <link name="base_link">
    <collision><origin xyz="-0.04 0 0.01"/><geometry><box size="0.3 0.18 0.06"/></geometry></collision>
    <inertial><origin xyz="-0.04 0 0.01"/><mass value="1.5"/>
      <inertia ixx="0.0045" ixy="0" ixz="0" iyy="0.0117" iyz="0" izz="0.0153"/></inertial>
  </link>)" +
         wheel_xml("left", 0.11, 0.045, 0.025, wheel_inertial_left) + wheel_xml("right", -0.11) + R"(
  <link name="caster_link">
    <collision><geometry><box size="0.04 0.04 0.04"/></geometry></collision>
  </link>
  <joint name="caster_joint" type=")" +
         caster_joint + R"(">
    <parent link="base_link"/><child link="caster_link"/><origin xyz="-0.15 0 -0.025"/><axis xyz="0 0 1"/>
  </joint>
</robot>
)";
}

UrdfMapping diff_mapping(bool caster) {
  UrdfMapping m;
  m.wheels = {{{}, "left", "left_wheel_joint"}, {{}, "right", "right_wheel_joint"}};
  if (caster) m.casters = {{{}, "caster_link", 0}};
  return m;
}

const char* kWheelInertial = R"(<inertial><mass value="0.06"/>
      <inertia ixx="3.35e-5" ixy="0" ixz="0" iyy="6.075e-5" iyz="0" izz="3.35e-5"/></inertial>)";

TEST(UrdfImport, WheelsBecomeCylindersOnTheirJointAxis) {
  TempDir dir;
  const Imported in = import_text(dir.path(), diff_drive(kWheelInertial), diff_mapping(true));
  ASSERT_TRUE(in.ok) << in.diagnostics.joined();
  ASSERT_EQ(in.robot.wheels.size(), 2u);
  const WheelDesc& left = in.robot.wheels[0];
  EXPECT_EQ(left.name, "left");
  EXPECT_NEAR(left.radius_m, 0.045, 1e-12);
  EXPECT_NEAR(left.width_m, 0.025, 1e-12);
  EXPECT_DOUBLE_EQ(left.mass_kg, 0.06);
  // The axle at base_link's (0, 0.11, 0), in the chassis frame whose origin is the centre of mass.
  const Eigen::Vector3d base = in.robot.report.base_origin_m;
  EXPECT_TRUE((left.position_m - base).isApprox(Eigen::Vector3d(0, 0.11, 0), 1e-12)) << left.position_m.transpose();
  // The wheel body's z runs along the axle: the URDF's iyy (about y) is its izz.
  EXPECT_NEAR(left.inertia_kgm2(2, 2), 6.075e-5, 1e-15);
  EXPECT_NEAR(left.inertia_kgm2(0, 0), 3.35e-5, 1e-15);
}

TEST(UrdfImport, FixedCasterBoxSlidesUnlessMappedAsACaster) {
  TempDir dir;
  const std::string text = diff_drive(kWheelInertial);
  // Without the mapping, the box stays a chassis shape down where the tyres touch: a warning at it.
  const Imported plain = import_text(dir.path(), text, diff_mapping(false));
  ASSERT_TRUE(plain.ok) << plain.diagnostics.joined();
  const auto* w = find_warning(plain.robot, "will slide over the floor");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->first.line, line_of(text, "<box size=\"0.04 0.04 0.04\"/>"));
  EXPECT_NE(w->second.find("<caster link=\"caster_link\"/>"), std::string::npos) << w->second;
  EXPECT_EQ(plain.robot.chassis.parts.size(), 2u);

  // Mapped: a ball of half the box's height whose bottom stays at the box's, -0.045 m under base_link.
  const Imported mapped = import_text(dir.path(), text, diff_mapping(true));
  ASSERT_TRUE(mapped.ok) << mapped.diagnostics.joined();
  EXPECT_EQ(find_warning(mapped.robot, "will slide"), nullptr);
  ASSERT_EQ(mapped.robot.casters.size(), 1u);
  EXPECT_NEAR(mapped.robot.casters[0].radius_m, 0.02, 1e-12);
  const Eigen::Vector3d ball = mapped.robot.casters[0].position_m - mapped.robot.report.base_origin_m;
  EXPECT_TRUE(ball.isApprox(Eigen::Vector3d(-0.15, 0, -0.025), 1e-12)) << ball.transpose();
  EXPECT_EQ(mapped.robot.chassis.parts.size(), 1u);  // the box is no longer a chassis shape
  // A caster on a swivel joint is held and lumped the same way.
  const Imported swivel = import_text(dir.path(), diff_drive(kWheelInertial, "continuous"), diff_mapping(true));
  ASSERT_TRUE(swivel.ok) << swivel.diagnostics.joined();
  EXPECT_NEAR(swivel.robot.casters[0].radius_m, 0.02, 1e-12);
}

TEST(UrdfImport, MasslessMovingLinkIsRefusedAtItsLine) {
  TempDir dir;
  const std::string text = diff_drive("");
  const Imported in = import_text(dir.path(), text, diff_mapping(true));
  EXPECT_FALSE(in.ok);
  const Diagnostic* e = find_error(in.diagnostics, "link 'left_wheel' moves (joint 'left_wheel_joint') but has no <inertial>");
  ASSERT_NE(e, nullptr) << in.diagnostics.joined();
  EXPECT_EQ(e->line, line_of(text, "<link name=\"left_wheel\">"));
  EXPECT_EQ(e->file, in.path);

  // A density derives it from the wheel's cylinder: 1000 kg/m^3 * pi * 0.045^2 * 0.025 m^3.
  UrdfMapping with = diff_mapping(true);
  with.densities.push_back({{}, "left_wheel", 1000});
  const Imported derived = import_text(dir.path(), text, with);
  ASSERT_TRUE(derived.ok) << derived.diagnostics.joined();
  EXPECT_NEAR(derived.robot.wheels[0].mass_kg, 1000 * M_PI * 0.045 * 0.045 * 0.025, 1e-12);
  // About the axle a solid cylinder has m r^2 / 2.
  EXPECT_NEAR(derived.robot.wheels[0].inertia_kgm2(2, 2), 0.5 * derived.robot.wheels[0].mass_kg * 0.045 * 0.045, 1e-15);
  EXPECT_NE(find_warning(derived.robot, "derived from its collision shapes"), nullptr);
}

TEST(UrdfImport, PlaceholderAndNonPhysicalInertiasAreRefusedAtTheirLine) {
  TempDir dir;
  struct Case {
    const char* inertia;
    const char* reason;
  };
  // A 0.1 m cube of 1 kg: a real one has I = m (0.1^2 + 0.1^2) / 12 = 0.00167 kg*m^2 about each axis.
  for (const Case& c : {Case{R"(ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1")", "radius of gyration"},
                        Case{R"(ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="-0.001")", "not positive definite"},
                        Case{R"(ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.003")", "triangle inequality"},
                        Case{R"(ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0")", "not positive definite"}}) {
    SCOPED_TRACE(c.reason);
    const std::string text = std::string(R"(<robot name="p">
  <link name="base_link">
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
    <inertial>
      <mass value="1"/>
      <inertia )") + c.inertia + R"(/>
    </inertial>
  </link>
</robot>)";
    const Imported in = import_text(dir.path(), text);
    EXPECT_FALSE(in.ok);
    const Diagnostic* e = find_error(in.diagnostics, c.reason);
    ASSERT_NE(e, nullptr) << in.diagnostics.joined();
    EXPECT_EQ(e->line, line_of(text, "<inertia "));
    // With a density the cube's own follows: 500 kg/m^3 * 0.001 m^3.
    UrdfMapping m;
    m.densities.push_back({{}, "", 500});
    const Imported derived = import_text(dir.path(), text, m);
    ASSERT_TRUE(derived.ok) << derived.diagnostics.joined();
    EXPECT_NEAR(derived.robot.chassis.mass_kg, 0.5, 1e-12);
    EXPECT_NEAR(derived.robot.chassis.inertia_kgm2(0, 0), 0.5 * 0.02 / 12, 1e-15);
  }
  // Zero mass is refused at the <mass>.
  const std::string text = R"(<robot name="z">
  <link name="base_link">
    <inertial>
      <mass value="0"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/>
    </inertial>
  </link>
</robot>)";
  const Imported in = import_text(dir.path(), text);
  const Diagnostic* e = find_error(in.diagnostics, "mass 0 kg is not positive");
  ASSERT_NE(e, nullptr) << in.diagnostics.joined();
  EXPECT_EQ(e->line, line_of(text, "<mass value=\"0\"/>"));
}

TEST(UrdfImport, UnexpandedXacroIsRefusedAndAPlainArgumentSubstituted) {
  TempDir dir;
  const std::string text = R"(<?xml version="1.0"?>
<robot name="ns">
  <link name="${namespace}base_link">
    <inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
</robot>)";
  const Imported in = import_text(dir.path(), text);
  EXPECT_FALSE(in.ok);
  const Diagnostic* e = find_error(in.diagnostics, "unexpanded xacro expression '${namespace}'");
  ASSERT_NE(e, nullptr) << in.diagnostics.joined();
  EXPECT_EQ(e->line, 3);
  EXPECT_NE(e->message.find("not available in Debian 12"), std::string::npos);
  UrdfMapping m;
  m.args["namespace"] = "bot1_";
  const Imported named = import_text(dir.path(), text, m);
  ASSERT_TRUE(named.ok) << named.diagnostics.joined();
  EXPECT_TRUE(named.robot.links.count("bot1_base_link"));
  // An expression is xacro's to work out, not ours.
  const std::string expr = R"(<robot name="e">
  <link name="base_link">
    <inertial><mass value="${2*m}"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
</robot>)";
  const Imported refused = import_text(dir.path(), expr, m);
  const Diagnostic* x = find_error(refused.diagnostics, "'${2*m}'");
  ASSERT_NE(x, nullptr) << refused.diagnostics.joined();
  EXPECT_EQ(x->line, 3);
}

TEST(UrdfImport, FloatingAndPlanarJointsAreRefusedAtTheirLine) {
  TempDir dir;
  for (const std::string type : {"floating", "planar"}) {
    const std::string text = R"(<robot name="f">
  <link name="base_link">
    <inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="drone"/>
  <joint name="free" type=")" + type + R"(">
    <parent link="base_link"/><child link="drone"/>
  </joint>
</robot>)";
    const Imported in = import_text(dir.path(), text);
    EXPECT_FALSE(in.ok);
    const Diagnostic* e = find_error(in.diagnostics, "joint 'free' is " + type);
    ASSERT_NE(e, nullptr) << in.diagnostics.joined();
    EXPECT_EQ(e->line, line_of(text, "<joint name=\"free\""));
  }
}

TEST(UrdfImport, UnmappedMovingJointIsLiveAndAFrozenOneLumped) {
  TempDir dir;
  const std::string text = R"(<robot name="arm">
  <link name="base_link">
    <inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="lift"><inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <joint name="lift_joint" type="prismatic">
    <parent link="base_link"/><child link="lift"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="0.3" effort="10" velocity="0.1"/>
    <dynamics damping="2" friction="0.5"/>
  </joint>
</robot>)";
  // Named neither as a wheel nor held: a passive slider with the URDF's stops and dynamics.
  const Imported in = import_text(dir.path(), text);
  ASSERT_TRUE(in.ok) << in.diagnostics.joined();
  ASSERT_EQ(in.robot.joints.size(), 1u);
  const JointLinkDesc& j = in.robot.joints[0];
  EXPECT_EQ(j.kind, JointLinkDesc::Kind::Slider);
  EXPECT_EQ(j.link, "lift");
  EXPECT_EQ(j.source.line, line_of(text, "<joint name=\"lift_joint\""));
  EXPECT_TRUE(j.limited);
  EXPECT_DOUBLE_EQ(j.lower, 0.0);
  EXPECT_DOUBLE_EQ(j.upper, 0.3);
  EXPECT_DOUBLE_EQ(j.effort, 10.0);
  EXPECT_DOUBLE_EQ(j.velocity, 0.1);
  EXPECT_DOUBLE_EQ(j.damping, 2.0);
  EXPECT_DOUBLE_EQ(j.friction, 0.5);
  EXPECT_DOUBLE_EQ(j.mass_kg, 1.0);
  EXPECT_DOUBLE_EQ(in.robot.chassis.mass_kg, 1.0);  // the lift is not lumped into the chassis
  EXPECT_TRUE(j.axis.isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  EXPECT_FALSE(in.robot.links.at("lift").on_chassis);
  UrdfMapping m;
  m.freezes.push_back({{}, "lift_joint", 0.2});
  const Imported frozen = import_text(dir.path(), text, m);
  ASSERT_TRUE(frozen.ok) << frozen.diagnostics.joined();
  EXPECT_TRUE(frozen.robot.joints.empty());
  // Two 1 kg masses 0.2 m apart in z: the centre halfway.
  EXPECT_TRUE(frozen.robot.report.base_origin_m.isApprox(Eigen::Vector3d(0, 0, -0.1), 1e-12));
  EXPECT_DOUBLE_EQ(frozen.robot.chassis.mass_kg, 2.0);
}

TEST(UrdfImport, LiveLinkIsABodyOfItsOwnAsAHandComputationHasIt) {
  TempDir dir;
  // base_link 2 kg at its origin. The upper arm hangs on a revolute joint 0.1 m ahead and 0.2 m
  // up, turned 90 degrees about z, its axis x (so the robot's y); its own 0.5 kg centre 0.05 m
  // along its x, and a 0.5 kg hand fixed 0.1 m further along it: together 1 kg at 0.1 m along
  // the arm's x, which is the robot's y.
  const std::string text = R"(<robot name="arm">
  <link name="base_link">
    <inertial><mass value="2"/><inertia ixx="0.002" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.002"/></inertial>
  </link>
  <link name="upper">
    <collision><origin xyz="0.05 0 0"/><geometry><box size="0.1 0.02 0.02"/></geometry></collision>
    <inertial><origin xyz="0.05 0 0"/><mass value="0.5"/><inertia ixx="1e-5" ixy="0" ixz="0" iyy="4e-4" iyz="0" izz="4e-4"/></inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/><child link="upper"/><origin xyz="0.1 0 0.2" rpy="0 0 1.5707963267948966"/>
    <axis xyz="1 0 0"/><limit lower="-0.5" upper="4" effort="1" velocity="2"/>
  </joint>
  <link name="hand">
    <inertial><mass value="0.5"/><inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial>
  </link>
  <joint name="wrist" type="fixed"><parent link="upper"/><child link="hand"/><origin xyz="0.15 0 0"/></joint>
</robot>)";
  const Imported in = import_text(dir.path(), text);
  ASSERT_TRUE(in.ok) << in.diagnostics.joined();
  ASSERT_EQ(in.robot.joints.size(), 1u);
  const JointLinkDesc& j = in.robot.joints[0];
  EXPECT_DOUBLE_EQ(in.robot.chassis.mass_kg, 2.0);
  EXPECT_DOUBLE_EQ(j.mass_kg, 1.0);
  const Eigen::Vector3d base = in.robot.report.base_origin_m;  // the chassis is base_link alone: 0
  EXPECT_TRUE(base.isZero(1e-12));
  EXPECT_TRUE(j.anchor_m.isApprox(Eigen::Vector3d(0.1, 0, 0.2), 1e-12)) << j.anchor_m.transpose();
  EXPECT_TRUE(j.position_m.isApprox(Eigen::Vector3d(0.1, 0.1, 0.2), 1e-12)) << j.position_m.transpose();
  EXPECT_TRUE(j.axis.isApprox(Eigen::Vector3d::UnitY(), 1e-12)) << j.axis.transpose();
  // About the common centre, in the arm's axes: the two 0.5 kg parts 0.05 m either side along x
  // add 2 * 0.5 * 0.05^2 = 2.5e-3 to iyy and izz.
  EXPECT_NEAR(j.inertia_kgm2(0, 0), 2e-5, 1e-12);
  EXPECT_NEAR(j.inertia_kgm2(1, 1), 4e-4 + 1e-5 + 2.5e-3, 1e-12);
  EXPECT_NEAR(j.inertia_kgm2(2, 2), 4e-4 + 1e-5 + 2.5e-3, 1e-12);
  // Its collision box, about the body's centre (0.05 m behind it along the arm's x).
  ASSERT_EQ(j.parts.size(), 1u);
  EXPECT_TRUE(j.parts[0].position_m.isApprox(Eigen::Vector3d(-0.05, 0, 0), 1e-12));
  // ODE measures a hinge's angle in -pi..pi: the upper stop at 4 rad is left out, with a warning.
  EXPECT_TRUE(j.limited);
  EXPECT_DOUBLE_EQ(j.lower, -0.5);
  EXPECT_TRUE(std::isinf(j.upper));
  const auto* w = find_warning(in.robot, "joint 'shoulder': ODE measures a hinge's angle in -pi..pi");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->first.line, line_of(text, "<joint name=\"shoulder\""));
}

TEST(UrdfImport, MovingJointOnAWheelAndBadLimitsAreRefusedAtTheirLines) {
  TempDir dir;
  const std::string text = R"(<robot name="w">
  <link name="base_link">
    <inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>)" + wheel_xml("left", 0.1) + R"(
  <link name="flag"><inertial><mass value="0.01"/><inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/></inertial></link>
  <joint name="flag_joint" type="continuous"><parent link="left_wheel"/><child link="flag"/><axis xyz="1 0 0"/></joint>
  <link name="tail"><inertial><mass value="0.01"/><inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/></inertial></link>
  <joint name="tail_joint" type="revolute"><parent link="base_link"/><child link="tail"/><axis xyz="0 0 1"/>
    <limit lower="0.5" upper="-0.5" effort="1" velocity="1"/><dynamics damping="-1"/></joint>
</robot>)";
  UrdfMapping m;
  m.wheels.push_back({{}, "left", "left_wheel_joint"});
  const Imported in = import_text(dir.path(), text, m);
  EXPECT_FALSE(in.ok);
  const Diagnostic* e = find_error(in.diagnostics, "joint 'flag_joint' hangs from wheel 'left'");
  ASSERT_NE(e, nullptr) << in.diagnostics.joined();
  EXPECT_EQ(e->line, line_of(text, "<joint name=\"flag_joint\""));
  e = find_error(in.diagnostics, "joint 'tail_joint': <limit lower=\"0.5\" upper=\"-0.5\">: lower is above upper");
  ASSERT_NE(e, nullptr) << in.diagnostics.joined();
  EXPECT_EQ(e->line, line_of(text, "<joint name=\"tail_joint\""));
  EXPECT_NE(find_error(in.diagnostics, "joint 'tail_joint': <dynamics damping=\"-1\"> is negative"), nullptr)
      << in.diagnostics.joined();
}

TEST(UrdfImport, NearRightAnglesAreSnappedWithAWarning) {
  TempDir dir;
  // The usual way to lay a cylinder's z along y, written with 1.5708 for pi/2.
  const std::string text = R"(<robot name="s">
  <link name="base_link">
    <inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="left_wheel">
    <collision><geometry><cylinder radius="0.05" length="0.02"/></geometry></collision>
    <inertial><mass value="0.1"/><inertia ixx="7e-5" ixy="0" ixz="0" iyy="7e-5" iyz="0" izz="1.25e-4"/></inertial>
  </link>
  <joint name="left_wheel_joint" type="continuous">
    <parent link="base_link"/><child link="left_wheel"/>
    <origin xyz="0 0.1 0" rpy="-1.5708 0 0"/>
    <axis xyz="0 0 1"/>
  </joint>
</robot>)";
  UrdfMapping m;
  m.wheels = {{{}, "left", "left_wheel_joint"}};
  const Imported in = import_text(dir.path(), text, m);
  ASSERT_TRUE(in.ok) << in.diagnostics.joined();
  const auto* w = find_warning(in.robot, "rpy=\"-1.5708 0 0\"");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->first.line, line_of(text, "rpy=\"-1.5708 0 0\""));
  // Exactly a quarter turn, where 1.5708 would leave the axle 3.7e-6 rad off the y axis.
  const Eigen::Matrix3d quarter = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_LT((in.robot.links.at("left_wheel").rotation - quarter).cwiseAbs().maxCoeff(), 1e-15);
  ASSERT_EQ(in.robot.wheels.size(), 1u);
  EXPECT_NEAR(in.robot.wheels[0].radius_m, 0.05, 1e-12);
  EXPECT_NEAR(in.robot.wheels[0].width_m, 0.02, 1e-12);
  EXPECT_NEAR(in.robot.wheels[0].inertia_kgm2(2, 2), 1.25e-4, 1e-15);  // about the axle
}

TEST(UrdfImport, HeavyBodyMeshBecomesItsBoxWhenTheMappingAsks) {
  TempDir dir;
  // 20 x 20 squares a face: 6 * 2 * 400 = 4800 triangles.
  write_text(dir.path() / "body.stl", box_stl(0.2, 0.1, 0.05, 20));
  const std::string text = R"(<robot name="h">
  <link name="base_link">
    <collision><origin xyz="0.01 0 0"/><geometry><mesh filename="body.stl"/></geometry></collision>
    <inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.0035" iyz="0" izz="0.004"/></inertial>
  </link>
</robot>)";
  UrdfMapping m;
  m.collisions.push_back({{}, "", 1000, UrdfMapping::Collision::Replace::None});
  const Imported kept = import_text(dir.path(), text, m);
  ASSERT_TRUE(kept.ok) << kept.diagnostics.joined();
  EXPECT_EQ(kept.robot.chassis.parts[0].kind, ShapeDesc::Kind::Mesh);
  const auto* w = find_warning(kept.robot, "4800 triangles, over the budget of 1000");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->first.line, 3);
  m.collisions[0].replace = UrdfMapping::Collision::Replace::Box;
  const Imported boxed = import_text(dir.path(), text, m);
  ASSERT_TRUE(boxed.ok) << boxed.diagnostics.joined();
  const ShapeDesc& box = boxed.robot.chassis.parts[0];
  EXPECT_EQ(box.kind, ShapeDesc::Kind::Box);
  EXPECT_TRUE(box.size_m.isApprox(Eigen::Vector3d(0.2, 0.1, 0.05), 1e-6));
  EXPECT_TRUE((box.position_m - boxed.robot.report.base_origin_m).isApprox(Eigen::Vector3d(0.01, 0, 0), 1e-6));
  EXPECT_NE(boxed.robot.report.meshes[0].decision.find("4800 triangles, over the budget of 1000"), std::string::npos)
      << boxed.robot.report.meshes[0].decision;
}

// Every face's plane holds its corners, its normal is a unit vector pointing away from the
// centre (the hulls here are centred on the origin), and its corners go counter-clockwise seen
// from outside (each fanned triangle's own normal along the face's).
void expect_well_formed(const ConvexHull& hull) {
  for (const auto& f : hull.faces) {
    EXPECT_NEAR(f.normal.norm(), 1.0, 1e-12);
    EXPECT_GT(f.offset, 0);  // the origin is inside
    for (auto k : f.corners) EXPECT_NEAR(f.normal.dot(hull.vertices[k]), f.offset, 1e-9);
    for (std::size_t k = 1; k + 1 < f.corners.size(); ++k) {
      const Eigen::Vector3d& a = hull.vertices[f.corners[0]];
      EXPECT_GT((hull.vertices[f.corners[k]] - a).cross(hull.vertices[f.corners[k + 1]] - a).dot(f.normal), 0);
    }
  }
}

// The signed volume of a closed triangle mesh: positive only when every triangle winds outward.
double mesh_volume(const TriangleMesh& mesh) {
  double six_v = 0;
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3)
    six_v += mesh.vertices[mesh.indices[t]].cast<double>().dot(
        mesh.vertices[mesh.indices[t + 1]].cast<double>().cross(mesh.vertices[mesh.indices[t + 2]].cast<double>()));
  return six_v / 6;
}

std::vector<Eigen::Vector3d> stl_points(const std::filesystem::path& file) {
  const MeshLoadResult loaded = load_mesh(file.string(), UpAxis::Z, 1.0);
  EXPECT_TRUE(loaded.error.empty()) << loaded.error;
  std::vector<Eigen::Vector3d> points;
  for (const auto& v : loaded.mesh.vertices) points.push_back(v.cast<double>());
  return points;
}

// A box whose faces are split into 4 x 4 squares: the squares' inner corners lie on the faces,
// so the hull keeps the 8 corners, and qhull merges each face's triangles into one square.
TEST(UrdfHull, ASubdividedBoxHasEightCornersSixSquareFacesAndItsVolume) {
  TempDir dir;
  write_text(dir.path() / "box.stl", box_stl(0.2, 0.1, 0.05, 4));
  const auto points = stl_points(dir.path() / "box.stl");
  ASSERT_GT(points.size(), 8u);  // a 5 x 5 grid of points on each face
  const ConvexHull hull = convex_hull(points);
  ASSERT_TRUE(hull.error.empty()) << hull.error;
  EXPECT_EQ(hull.vertices.size(), 8u);
  ASSERT_EQ(hull.faces.size(), 6u);
  for (const auto& f : hull.faces) EXPECT_EQ(f.corners.size(), 4u);
  expect_well_formed(hull);
  // 0.2 x 0.1 x 0.05 m; the STL's corners are floats, each side within 2^-24 of its own length,
  // the volume within 3 * 2^-24 of its own.
  EXPECT_NEAR(hull_volume(hull), 0.2 * 0.1 * 0.05, 3 * std::ldexp(0.001, -24));
  // The triangles ODE and the viewer get: two a square, wound outward (the same volume, not its
  // negative; their corners rounded to float once more).
  const TriangleMesh triangles = hull_triangles(hull);
  EXPECT_EQ(triangles.indices.size(), 3u * 12u);
  EXPECT_NEAR(mesh_volume(triangles), 0.2 * 0.1 * 0.05, 6 * std::ldexp(0.001, -24));
}

TEST(UrdfHull, AnOctahedronHasSixCornersEightTrianglesAndFourThirdsRCubed) {
  TempDir dir;
  const double r = 0.03;
  write_text(dir.path() / "octahedron.stl", octahedron_stl(r));
  std::vector<Eigen::Vector3d> points = stl_points(dir.path() / "octahedron.stl");
  // Points inside change nothing: the centre and a point halfway to a corner.
  points.push_back(Eigen::Vector3d::Zero());
  points.push_back(Eigen::Vector3d(0.5 * r, 0, 0));
  const ConvexHull hull = convex_hull(points);
  ASSERT_TRUE(hull.error.empty()) << hull.error;
  EXPECT_EQ(hull.vertices.size(), 6u);
  ASSERT_EQ(hull.faces.size(), 8u);
  expect_well_formed(hull);
  // Each face 1/sqrt(3) r from the centre.
  for (const auto& f : hull.faces) EXPECT_NEAR(f.offset, r / std::sqrt(3.0), 1e-9);
  // Two square pyramids of base 2 r^2 and height r: 4/3 r^3. The STL's corners are floats, r
  // within half a float ulp (2^-24 relative), so the volume within 3 * 2^-24 of it.
  const double volume = 4.0 / 3.0 * r * r * r;
  EXPECT_NEAR(hull_volume(hull), volume, 3 * std::ldexp(volume, -24));
  EXPECT_NEAR(mesh_volume(hull_triangles(hull)), volume, 6 * std::ldexp(volume, -24));
}

TEST(UrdfHull, FlatPointsHaveNoHullAndSayWhy) {
  const ConvexHull hull = convex_hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.5, 0}});
  EXPECT_FALSE(hull.error.empty());
  EXPECT_TRUE(hull.faces.empty());
  EXPECT_EQ(convex_hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).error, "fewer than 4 points");
}

TEST(UrdfImport, HeavyBodyMeshBecomesItsHullWhenTheMappingAsks) {
  TempDir dir;
  write_text(dir.path() / "body.stl", box_stl(0.2, 0.1, 0.05, 20));  // 4800 triangles
  const std::string text = R"(<robot name="h">
  <link name="base_link">
    <collision><origin xyz="0.01 0 0"/><geometry><mesh filename="body.stl"/></geometry></collision>
    <inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.0035" iyz="0" izz="0.004"/></inertial>
  </link>
</robot>)";
  UrdfMapping m;
  m.collisions.push_back({{}, "", 1000, UrdfMapping::Collision::Replace::Hull});
  const Imported hulled = import_text(dir.path(), text, m);
  ASSERT_TRUE(hulled.ok) << hulled.diagnostics.joined();
  EXPECT_TRUE(hulled.robot.report.warnings.empty());
  const ShapeDesc& part = hulled.robot.chassis.parts[0];
  EXPECT_EQ(part.kind, ShapeDesc::Kind::Mesh);
  EXPECT_EQ(part.mesh.vertices.size(), 8u);
  EXPECT_EQ(part.mesh.indices.size(), 3u * 12u);
  EXPECT_TRUE((part.position_m - hulled.robot.report.base_origin_m).isApprox(Eigen::Vector3d(0.01, 0, 0), 1e-6));
  EXPECT_EQ(hulled.robot.report.meshes[0].decision,
            "convex hull, 8 vertices, 6 faces, 12 triangles (4800 triangles, over the budget of 1000)");

  // A flat mesh has no hull: refused at its <collision>.
  write_text(dir.path() / "body.stl", R"(solid flat
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 1 0 0
  vertex 1 1 0
 endloop
endfacet
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 1 1 0
  vertex 0 1 0
 endloop
endfacet
endsolid flat
)");
  m.collisions[0].max_triangles = 1;
  const Imported flat = import_text(dir.path(), text, m);
  EXPECT_FALSE(flat.ok);
  const Diagnostic* e = find_error(flat.diagnostics, "has no convex hull");
  ASSERT_NE(e, nullptr) << flat.diagnostics.joined();
  EXPECT_EQ(e->line, 3);
}

TEST(UrdfImport, PackagePathsResolveThroughTheMappingOrAFolderOfThatName) {
  TempDir dir;
  write_text(dir.path() / "mybot/meshes/body.stl", box_stl(0.2, 0.1, 0.05));
  const std::string text = R"(<robot name="pk">
  <link name="base_link">
    <visual><geometry><mesh filename="package://mybot/meshes/body.stl"/></geometry></visual>
    <visual><geometry><mesh filename="package://other/meshes/body.stl"/></geometry></visual>
    <inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
</robot>)";
  // The URDF inside mybot/urdf/: package mybot is that folder; 'other' is unknown.
  const Imported in = import_text(dir.path(), text, {}, "mybot/urdf/robot.urdf");
  EXPECT_FALSE(in.ok);
  EXPECT_EQ(in.diagnostics.count(), 1u) << in.diagnostics.joined();
  const Diagnostic* e = find_error(in.diagnostics, "package 'other', which is not known");
  ASSERT_NE(e, nullptr) << in.diagnostics.joined();
  EXPECT_EQ(e->line, 4);
  UrdfMapping m;
  m.packages["other"] = (dir.path() / "mybot").string();
  const Imported both = import_text(dir.path(), text, m, "mybot/urdf/robot.urdf");
  ASSERT_TRUE(both.ok) << both.diagnostics.joined();
  EXPECT_EQ(both.robot.report.meshes.size(), 2u);
}

}  // namespace
}  // namespace sear::test
