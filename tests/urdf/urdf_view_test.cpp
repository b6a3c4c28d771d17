// The viewer's scene for an imported robot (PROTOCOL.md section 2): the URDF's visuals, each in
// the frame of the body that carries it in the simulation, and the chassis' collision shapes in
// the physics overlay.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "../temp_dir.hpp"
#include "../test_world.hpp"
#include "scene/project_loader.hpp"
#include "urdf_files.hpp"
#include "view/frame_json.hpp"
#include "view/scene_json.hpp"

namespace sear::test {
namespace {

using Json = nlohmann::json;

// The scene gives lengths to 1 mm (round_mm): two rounded values differ from the true
// difference by at most 1 mm. Quaternion components go to 1e-4 (round_unit), which turns and
// scales a point by up to about 2e-4 of its distance: 1e-5 m within the 45 mm wheel.
constexpr double kRounding = 1e-3 + 1e-5;

Eigen::Vector3d vec(const Json& j) { return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()}; }
Eigen::Quaterniond quat(const Json& j) {
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>(), j[3].get<double>()};
}

// A visual mesh's vertices placed by its pos and quat: their bounds in its body's frame.
void placed_bounds(const Json& v, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  lo = Eigen::Vector3d::Constant(1e9);
  hi = -lo;
  const auto& xs = v["vertices"];
  for (std::size_t i = 0; i + 2 < xs.size(); i += 3) {
    const Eigen::Vector3d p = vec(v["pos"]) + quat(v["quat"]) * Eigen::Vector3d(xs[i], xs[i + 1], xs[i + 2]);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
}

TEST(UrdfView, SceneCarriesTheVisualsOnTheirBodies) {
  Diagnostics diagnostics;
  const auto project = load_project(std::string(SEAR_ASSET_DIR) + "/projects/avoider_urdf.xml", diagnostics);
  ASSERT_TRUE(project) << diagnostics.joined();
  const Json scene = Json::parse(scene_json(*project));
  const Json& robot = scene["robots"][0];
  ASSERT_TRUE(robot.contains("visuals"));
  // The chassis STL, two wheels, the caster sphere and three ranger housings.
  ASSERT_EQ(robot["visuals"].size(), 7u);
  const Eigen::Vector3d base = project->robots[0].urdf.base_origin_m;
  for (const Json& v : robot["visuals"]) {
    SCOPED_TRACE(v["link"].get<std::string>());
    const int body = v["body"].get<int>();
    if (v["link"] == "base_link") {
      EXPECT_EQ(body, -1);
      Eigen::Vector3d lo, hi;
      placed_bounds(v, lo, hi);
      // 300 x 180 x 60 mm about (-0.04, 0, 0.01) in base_link, drawn in the chassis frame. The
      // scene rounds vertices and positions to 1 mm: a side is good to 1 mm (both ends rounded),
      // a centre to 1 mm (its position and the vertices each to 0.5 mm).
      EXPECT_LT(((hi - lo) - Eigen::Vector3d(0.3, 0.18, 0.06)).cwiseAbs().maxCoeff(), kRounding) << (hi - lo).transpose();
      EXPECT_LT(((0.5 * (hi + lo) - base) - Eigen::Vector3d(-0.04, 0, 0.01)).cwiseAbs().maxCoeff(), kRounding)
          << (0.5 * (hi + lo) - base).transpose();
    } else if (v["link"] == "left_wheel" || v["link"] == "right_wheel") {
      EXPECT_EQ(body, v["link"] == "left_wheel" ? 0 : 1);
      // On its wheel body, whose z is the axle: the tyre's 25 mm width lies along z, centred.
      Eigen::Vector3d lo, hi;
      placed_bounds(v, lo, hi);
      EXPECT_NEAR(hi.z() - lo.z(), 0.025, kRounding);
      EXPECT_NEAR(hi.x() - lo.x(), 0.09, kRounding);
      EXPECT_NEAR(hi.y() - lo.y(), 0.09, kRounding);
      EXPECT_LT((0.5 * (hi + lo)).cwiseAbs().maxCoeff(), kRounding);
    } else {
      EXPECT_EQ(body, -1);
    }
  }
  // The physics overlay shows the chassis' collision box, not a stand-in.
  int chassis_geoms = 0;
  for (const Json& g : robot["geoms"])
    if (g["part"] == "chassis") {
      ++chassis_geoms;
      EXPECT_EQ(g["shape"], "box");
      EXPECT_TRUE(vec(g["size"]).isApprox(Eigen::Vector3d(0.3, 0.18, 0.06), 1e-9));
    }
  EXPECT_EQ(chassis_geoms, 1);
}

TEST(UrdfView, LiveLinkIsDrawnWhereItsBodyIs) {
  // A 0.2 kg ball 0.15 m out along y on a hinge about x, 0.3 m above base_link: it falls onto
  // its stop at -1 rad.
  TempDir dir;
  const std::string urdf = (dir.path() / "swing.urdf").string();
  write_text(urdf, R"(<robot name="swing">
  <link name="base_link">
    <collision><geometry><box size="0.3 0.2 0.05"/></geometry></collision>
    <inertial><mass value="20"/><inertia ixx="0.0708" ixy="0" ixz="0" iyy="0.1542" iyz="0" izz="0.2167"/></inertial>
  </link>)" + wheel_xml("left", 0.12) + wheel_xml("right", -0.12) + R"(
  <link name="caster"><collision><geometry><sphere radius="0.0225"/></geometry></collision>
    <inertial><mass value="0.02"/><inertia ixx="4e-6" ixy="0" ixz="0" iyy="4e-6" iyz="0" izz="4e-6"/></inertial></link>
  <joint name="caster_joint" type="fixed"><parent link="base_link"/><child link="caster"/><origin xyz="-0.12 0 -0.0225"/></joint>
  <link name="bob">
    <collision><origin xyz="0 0.15 0"/><geometry><sphere radius="0.02"/></geometry></collision>
    <visual><origin xyz="0 0.15 0"/><geometry><sphere radius="0.02"/></geometry><material name="red"><color rgba="1 0 0 1"/></material></visual>
    <inertial><origin xyz="0 0.15 0"/><mass value="0.2"/><inertia ixx="3.2e-5" ixy="0" ixz="0" iyy="3.2e-5" iyz="0" izz="3.2e-5"/></inertial>
  </link>
  <joint name="bob_joint" type="revolute"><parent link="base_link"/><child link="bob"/>
    <origin xyz="0 0 0.3"/><axis xyz="1 0 0"/><limit lower="-1" upper="0.5" effort="1" velocity="20"/></joint>
</robot>)");
  const ProjectDesc project = project_from_xml(project_xml(R"(step="0.001")", "", R"(
  <robot name="swing" urdf=")" + urdf + R"(">
    <wheel name="left" joint="left_wheel_joint"/>
    <wheel name="right" joint="right_wheel_joint"/>
    <caster link="caster"/>
  </robot>)"));
  // The scene: the ball's visual and its collision sphere on live joint 0's body, whose origin
  // is the link's centre of mass, the ball's centre.
  const Json scene = Json::parse(scene_json(project));
  const Json& robot = scene["robots"][0];
  ASSERT_EQ(robot["joints"].size(), 1u);
  EXPECT_EQ(robot["joints"][0]["name"], "bob_joint");
  EXPECT_EQ(robot["joints"][0]["kind"], "hinge");
  ASSERT_EQ(robot["joints"][0]["geoms"].size(), 1u);
  EXPECT_LT(vec(robot["joints"][0]["geoms"][0]["pos"]).norm(), kRounding);
  int on_joint = 0;
  for (const Json& v : robot["visuals"])
    if (v["link"] == "bob") {
      ++on_joint;
      EXPECT_TRUE(v["body"].is_null());
      EXPECT_EQ(v["joint"], 0);
      EXPECT_LT(vec(v["pos"]).norm(), kRounding);
    } else {
      EXPECT_FALSE(v.contains("joint"));
    }
  EXPECT_EQ(on_joint, 1);

  // A frame once it rests on its stop: the link's pose, in the world, puts the ball 0.15 m from
  // the pivot turned by the joint's angle about the chassis' x.
  Simulation sim(project, 1);
  run_for(sim, 1.0);
  FrameWorld world(project);
  nlohmann::ordered_json frame;
  world.put(sim, {}, frame);
  const auto& fr = frame["robots"][0];
  ASSERT_EQ(fr["joints"].size(), 1u);
  const double q = fr["joints"][0]["q"].get<double>();
  EXPECT_NEAR(q, -1.0, 1e-3);
  const Eigen::Quaterniond chassis = quat(Json::parse(fr["quat"].dump())).normalized();
  const Eigen::Vector3d pivot = vec(Json::parse(fr["pos"].dump())) +
                                chassis * (project.robots[0].urdf.base_origin_m + Eigen::Vector3d(0, 0, 0.3));
  const Eigen::Vector3d ball = vec(Json::parse(fr["joints"][0]["pos"].dump()));
  const Eigen::Vector3d expected = pivot + chassis * (Eigen::AngleAxisd(q, Eigen::Vector3d::UnitX()) * Eigen::Vector3d(0, 0.15, 0));
  // The frame gives both positions to 1 mm, so each axis differs by up to 1 mm; its quaternion
  // (1e-4) and angle (1e-4 rad) move the 0.34 m from the chassis origin to the ball by 1e-4 m more.
  EXPECT_LT((ball - expected).cwiseAbs().maxCoeff(), 1e-3 + 1e-4) << ball.transpose() << " / " << expected.transpose();
}

}  // namespace
}  // namespace sear::test
