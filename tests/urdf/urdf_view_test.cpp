// The viewer's scene for an imported robot (PROTOCOL.md section 2): the URDF's visuals, each in
// the frame of the body that carries it in the simulation, and the chassis' collision shapes in
// the physics overlay.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "scene/project_loader.hpp"
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

}  // namespace
}  // namespace sear::test
