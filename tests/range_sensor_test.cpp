// Range sensing: the ray pattern of a cone bundle, and distances to boxes, trees, walls, terrain and
// meshes checked against their geometry; a robot does not see itself; a wide beam sees a thin pole.
#include "sensors/range_sensor.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "physics/physics_world.hpp"
#include "ray_fixture.hpp"
#include "temp_dir.hpp"
#include "test_world.hpp"

namespace sear {
namespace {

constexpr double kDeg = M_PI / 180.0;

using test::DefaultWorld;
using test::entity_of;
using test::Scene;

RangeBeam beam_at(const Eigen::Vector3d& position, double yaw_deg, double pitch_deg = 0, double max_range = 10,
                  double half_angle_deg = 0) {
  RangeBeam beam;
  beam.position_m = position;
  beam.yaw_rad = yaw_deg * kDeg;
  beam.pitch_rad = pitch_deg * kDeg;
  beam.max_range_m = max_range;
  beam.half_angle_rad = half_angle_deg * kDeg;
  return beam;
}

// A sensor placed in the world (no mount body) that ignores nothing.
RangeReading measure_at(const Scene& scene, const RangeBeam& beam) {
  return RangeSensor(beam).measure(scene.physics, nullptr, -1);
}

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

TEST(RangeSensorRays, CountFollowsTheFormulaAndEveryRayLiesInsideTheCone) {
  // Hand counts: 1 axis ray + max(3, ceil(pi / asin(sin(delta/2) / sin(theta)))) per cone.
  struct Case {
    double alpha_deg, delta_deg;
    std::vector<int> per_cone;  // outermost first
  };
  const std::vector<Case> cases = {{5, 1, {32, 26, 19, 13, 6}},
                                   {15, 2, {47, 41, 35, 29, 22, 16, 10, 3}},
                                   {2.5, 1, {16, 10, 3}},
                                   {12.5, 2.5, {32, 25, 19, 13, 6}},
                                   {0.4, 1, {3}}};
  for (const auto& c : cases) {
    RangeBeam beam = beam_at({0.1, 0.2, 0.3}, 30, 10, 1, c.alpha_deg);
    beam.resolution_rad = c.delta_deg * kDeg;
    const RangeSensor sensor(beam);
    const auto& rays = sensor.directions();
    int total = 1;
    for (int n : c.per_cone) total += n;
    ASSERT_EQ(rays.size(), static_cast<std::size_t>(total)) << c.alpha_deg << "/" << c.delta_deg;

    const double alpha = c.alpha_deg * kDeg, delta = c.delta_deg * kDeg;
    const Eigen::Vector3d axis = rays[0];
    for (const auto& d : rays) {
      EXPECT_NEAR(d.norm(), 1.0, 1e-12);
      EXPECT_LE(angle_between(axis, d), alpha + 1e-12);
    }
    for (std::size_t k = 0; k < c.per_cone.size(); ++k) {
      const double theta = alpha - static_cast<double>(k) * delta;
      EXPECT_EQ(RangeSensor::rays_on_cone(theta, delta), c.per_cone[k]);
      std::vector<Eigen::Vector3d> cone;
      for (const auto& d : rays)
        if (std::abs(angle_between(axis, d) - theta) < 1e-9) cone.push_back(d);
      ASSERT_EQ(cone.size(), static_cast<std::size_t>(c.per_cone[k])) << "cone at " << theta / kDeg << " deg";
      for (std::size_t i = 0; i < cone.size(); ++i) {
        double nearest = M_PI;
        for (std::size_t j = 0; j < cone.size(); ++j)
          if (j != i) nearest = std::min(nearest, angle_between(cone[i], cone[j]));
        EXPECT_LE(nearest, delta + 1e-12);
      }
    }
    // No direction in the beam is far from a ray: rings half a step apart radially and half a
    // neighbour gap apart around put the worst at about sqrt(2)/2 delta.
    const Eigen::Vector3d side = axis.unitOrthogonal(), up = axis.cross(side);
    for (int i = 0; i <= 40; ++i) {
      for (int j = 0; j < 72; ++j) {
        const double psi = alpha * i / 40, phi = 2 * M_PI * j / 72;
        const Eigen::Vector3d probe =
            std::cos(psi) * axis + std::sin(psi) * (std::cos(phi) * side + std::sin(phi) * up);
        double nearest = M_PI;
        for (const auto& d : rays) nearest = std::min(nearest, angle_between(probe, d));
        ASSERT_LE(nearest, 0.75 * delta) << "psi " << psi / kDeg << " phi " << phi / kDeg;
      }
    }
  }
}

TEST(RangeSensorRays, ZeroHalfAngleIsOneRayAlongTheMountAxis) {
  const RangeSensor sensor(beam_at({0, 0, 0}, 30, 10));
  ASSERT_EQ(sensor.directions().size(), 1u);
  // Positive pitch tilts the beam down.
  const Eigen::Vector3d expected(std::cos(10 * kDeg) * std::cos(30 * kDeg), std::cos(10 * kDeg) * std::sin(30 * kDeg),
                                 -std::sin(10 * kDeg));
  EXPECT_NEAR((sensor.directions()[0] - expected).norm(), 0.0, 1e-12);
  EXPECT_EQ(RangeSensor::rays_on_cone(1 * kDeg, 1 * kDeg), 6);  // a hexagon: neighbours exactly delta apart
  EXPECT_EQ(RangeSensor::rays_on_cone(0.1 * kDeg, 1 * kDeg), 3);
}

TEST(RangeSensorRays, RefusesImpossibleBeams) {
  RangeBeam wide = beam_at({0, 0, 0}, 0, 0, 1, 90);
  EXPECT_THROW(RangeSensor{wide}, std::invalid_argument);
  RangeBeam coarse = beam_at({0, 0, 0}, 0, 0, 1, 5);
  coarse.resolution_rad = 0;
  EXPECT_THROW(RangeSensor{coarse}, std::invalid_argument);
  RangeBeam inverted = beam_at({0, 0, 0}, 0, 0, 1);
  inverted.min_range_m = 2;
  EXPECT_THROW(RangeSensor{inverted}, std::invalid_argument);
  RangeBeam dense = beam_at({0, 0, 0}, 0, 0, 1, 60);
  dense.resolution_rad = 0.05 * kDeg;
  EXPECT_THROW(RangeSensor{dense}, std::invalid_argument);
}

// A static crate whose -x face is the plane x = 1.8 (|y| <= 1.5, z 0..1), and a dynamic parcel
// whose +x face is x = -1.8 (|y| <= 0.2, z 0..0.4).
constexpr const char* kBoxes =
    R"(<box name="crate" pos="2 0" size="0.4 3 1"/><box name="parcel" pos="-2 0" size="0.4 0.4 0.4" mass="1"/>)";

TEST(RangeSensorHits, DistanceToABoxFaceIsExact) {
  const Scene scene(kBoxes);
  const int crate = entity_of(scene.physics, "crate"), parcel = entity_of(scene.physics, "parcel");
  for (double x0 : {-1.0, 0.0, 0.5, 1.2, 1.75}) {
    const RangeReading r = measure_at(scene, beam_at({x0, 0.3, 0.3}, 0));
    ASSERT_TRUE(r.hit) << x0;
    EXPECT_NEAR(r.distance_m, 1.8 - x0, 1e-9) << x0;
    EXPECT_NEAR(r.point_m.x(), 1.8, 1e-9);
    EXPECT_EQ(r.entity, crate);
  }
  for (double yaw : {20.0, -35.0}) {  // oblique: the face's plane along the ray
    const RangeReading r = measure_at(scene, beam_at({0, 0, 0.3}, yaw));
    ASSERT_TRUE(r.hit);
    EXPECT_NEAR(r.distance_m, 1.8 / std::cos(yaw * kDeg), 1e-9) << yaw;
  }
  for (double x0 : {0.0, 0.5}) {  // the parcel sits in the dynamic space
    const RangeReading r = measure_at(scene, beam_at({x0, 0, 0.2}, 180));
    ASSERT_TRUE(r.hit);
    EXPECT_NEAR(r.distance_m, x0 + 1.8, 1e-9);
    EXPECT_EQ(r.entity, parcel);
  }
}

TEST(RangeSensorHits, NothingWithinMaxRangeIsAMiss) {
  const Scene scene(kBoxes);
  const RangeReading short_of = measure_at(scene, beam_at({0, 0, 0.3}, 0, 0, 1.79));
  EXPECT_FALSE(short_of.hit);
  EXPECT_EQ(short_of.distance_m, 1.79);
  const RangeReading reaches = measure_at(scene, beam_at({0, 0, 0.3}, 0, 0, 1.81));
  EXPECT_TRUE(reaches.hit);
  EXPECT_NEAR(reaches.distance_m, 1.8, 1e-9);
  EXPECT_FALSE(measure_at(scene, beam_at({0, 0, 0.3}, 90, 0, 50)).hit);  // level over open ground
}

TEST(RangeSensorHits, BelowMinRangeReportsTheTrueDistance) {
  const Scene scene(kBoxes);
  RangeBeam beam = beam_at({1.75, 0, 0.3}, 0, 0, 0.8);
  beam.min_range_m = 0.1;
  const RangeReading close = measure_at(scene, beam);
  EXPECT_TRUE(close.hit);
  EXPECT_TRUE(close.below_min);
  EXPECT_NEAR(close.distance_m, 0.05, 1e-9);
  beam.position_m.x() = 1.6;
  const RangeReading inside = measure_at(scene, beam);
  EXPECT_TRUE(inside.hit);
  EXPECT_FALSE(inside.below_min);
  EXPECT_NEAR(inside.distance_m, 0.2, 1e-9);
}

TEST(RangeSensorHits, TreeTrunkAndCrown) {
  // Trunk: radius 0.1 about (3, 1), z 0..2; crown: radius 0.5 about (3, 1, 2).
  const Scene scene(R"(<tree name="oak" pos="3 1" trunk_radius="0.1" trunk_height="2" crown_radius="0.5"/>)");
  const int oak = entity_of(scene.physics, "oak");
  struct Case {
    Eigen::Vector3d from;
    double expected;  // 3 - sqrt(r^2 - offset^2)
  };
  for (const auto& c : {Case{{0, 1, 0.5}, 2.9}, Case{{0, 1.06, 0.5}, 3 - 0.08}, Case{{0, 1, 2}, 2.5},
                        Case{{0, 1.3, 2}, 3 - 0.4}}) {
    const RangeReading r = measure_at(scene, beam_at(c.from, 0));
    ASSERT_TRUE(r.hit);
    EXPECT_NEAR(r.distance_m, c.expected, 1e-9) << c.from.transpose();
    EXPECT_EQ(r.entity, oak);
  }
}

TEST(RangeSensorHits, DiagonalWall) {
  // Centre line x + y = 2, 0.1 m thick: the face towards the origin is n.p = sqrt(2) - 0.05, n = (1, 1)/sqrt(2).
  const Scene scene(R"(<wall name="fence" from="0 2" to="2 0" height="1" thickness="0.1"/>)");
  const double face = std::sqrt(2.0) - 0.05;
  for (double yaw : {45.0, 60.0, 30.0}) {
    const RangeReading r = measure_at(scene, beam_at({0, 0, 0.5}, yaw));
    ASSERT_TRUE(r.hit) << yaw;
    EXPECT_NEAR(r.distance_m, face * std::sqrt(2.0) / (std::cos(yaw * kDeg) + std::sin(yaw * kDeg)), 1e-9) << yaw;
    EXPECT_EQ(r.entity, entity_of(scene.physics, "fence"));
  }
}

TEST(RangeSensorHits, FlatGroundAtHeightOverSinPitch) {
  const Scene scene("");
  const double h = 0.3;
  for (double pitch : {10.0, 30.0, 60.0, 90.0}) {
    const RangeReading r = measure_at(scene, beam_at({1, -2, h}, 70, pitch));
    ASSERT_TRUE(r.hit) << pitch;
    EXPECT_NEAR(r.distance_m, h / std::sin(pitch * kDeg), 1e-9) << pitch;
    EXPECT_EQ(r.entity, -1);
  }
  // A 5 degree bundle pitched 30 degrees down: its lowest ray (on the outer cone, 32 rays, so one
  // points straight down the cone) leaves 35 degrees below level.
  RangeBeam bundle = beam_at({1, -2, h}, 70, 30, 10, 5);
  const RangeReading r = measure_at(scene, bundle);
  ASSERT_TRUE(r.hit);
  EXPECT_NEAR(r.distance_m, h / std::sin(35 * kDeg), 1e-9);
}

// A <terrain> of height(x, y) sampled n x n over 20 x 20 m about the origin, as a 16-bit PGM
// whose levels span [low, high] m.
template <class Height>
std::string heightmap(const test::TempDir& dir, const std::string& name, int n, double low, double high,
                      Height height) {
  std::string pgm = "P5\n" + std::to_string(n) + " " + std::to_string(n) + "\n65535\n";
  for (int row = 0; row < n; ++row) {
    for (int col = 0; col < n; ++col) {
      const double x = -10.0 + 20.0 * col / (n - 1), y = 10.0 - 20.0 * row / (n - 1);
      const auto v = static_cast<unsigned>(std::lround((height(x, y) - low) / (high - low) * 65535.0));
      pgm += {static_cast<char>(v >> 8), static_cast<char>(v & 0xff)};
    }
  }
  return R"(<terrain type="heightmap" image=")" + dir.write(name, pgm) + R"(" size="20 20" min_height=")" +
         std::to_string(low) + R"(" max_height=")" + std::to_string(high) + R"("/>)";
}

// The plane h = 1 + 0.1 y + 0.05 x as a 65 x 65 heightmap (as in terrain_test).
double plane_height(double x, double y) { return 1.0 + 0.1 * y + 0.05 * x; }

std::string sloped_heightmap(const test::TempDir& dir) {
  return heightmap(dir, "plane.pgm", 65, -0.5, 2.5, plane_height);
}

TEST(RangeSensorHits, HeightmapTerrainWhereTheRayMeetsItsPlane) {
  const test::TempDir dir;
  const Scene scene(sloped_heightmap(dir));
  for (const auto& [x0, y0] : std::vector<std::pair<double, double>>{{0, 0}, {3, -4}, {-6, 5}}) {
    for (double yaw : {0.0, 90.0, 200.0}) {
      for (double pitch : {35.0, 80.0}) {
        const double z0 = plane_height(x0, y0) + 0.4;
        const RangeReading r = measure_at(scene, beam_at({x0, y0, z0}, yaw, pitch));
        // z0 + t dz = 1 + 0.1 (y0 + t dy) + 0.05 (x0 + t dx), solved for t.
        const Eigen::Vector3d d(std::cos(pitch * kDeg) * std::cos(yaw * kDeg),
                                std::cos(pitch * kDeg) * std::sin(yaw * kDeg), -std::sin(pitch * kDeg));
        const double t = (plane_height(x0, y0) - z0) / (d.z() - 0.1 * d.y() - 0.05 * d.x());
        ASSERT_TRUE(r.hit) << x0 << ", " << y0 << " yaw " << yaw;
        // 16-bit levels over 3 m quantise heights to 0.05 mm.
        EXPECT_NEAR(r.distance_m, t, 2e-4) << x0 << ", " << y0 << " yaw " << yaw << " pitch " << pitch;
        EXPECT_NEAR(r.point_m.z(), plane_height(r.point_m.x(), r.point_m.y()), 1e-4);
      }
    }
  }
}

TEST(RangeSensorHits, MeshTerrain) {
  // The wedge rises from z = 0 at x = 0 to z = 1 at x = 4, |y| <= 1.
  const Scene scene(std::string(R"(<terrain type="mesh" file=")") + SEAR_TEST_DATA + R"(/meshes/wedge.obj"/>)");
  const RangeReading down = measure_at(scene, beam_at({2, 0, 3}, 0, 90));
  ASSERT_TRUE(down.hit);
  EXPECT_NEAR(down.distance_m, 2.5, 1e-6);
  // From (1, 0, 2) at 45 degrees down, s = t / sqrt(2): 2 - s = (1 + s) / 4, s = 1.4.
  const RangeReading slanted = measure_at(scene, beam_at({1, 0, 2}, 0, 45));
  ASSERT_TRUE(slanted.hit);
  EXPECT_NEAR(slanted.distance_m, 1.4 * std::sqrt(2.0), 1e-6);
}

TEST(RangeSensorHits, MeshObstacle) {
  // `up` at (3, 0): x 3..7, slope z = (x - 3) / 4. `down` at (-3, 5) turned 180 degrees: x -7..-3,
  // |y - 5| <= 1, a vertical face at x = -7 and the slope z = (-3 - x) / 4.
  const std::string wedge = std::string(SEAR_TEST_DATA) + "/meshes/wedge.obj";
  const Scene scene(fmt::format(R"(<mesh name="up" file="{0}" pos="3 0"/><mesh name="down" file="{0}" pos="-3 5" yaw_deg="180"/>)",
                                wedge));
  struct Case {
    Eigen::Vector3d from;
    double yaw_deg;
    double expected;
    const char* entity;
  };
  for (const auto& c : {Case{{0, 0, 0.5}, 0, 5, "up"}, Case{{0, 0.5, 0.25}, 0, 4, "up"},
                        Case{{-10, 5, 0.5}, 0, 3, "down"}, Case{{0, 5, 0.5}, 180, 5, "down"}}) {
    const RangeReading r = measure_at(scene, beam_at(c.from, c.yaw_deg));
    ASSERT_TRUE(r.hit) << c.from.transpose();
    EXPECT_NEAR(r.distance_m, c.expected, 1e-6) << c.from.transpose();
    EXPECT_EQ(r.entity, entity_of(scene.physics, c.entity));
  }
}

TEST(RangeSensorHits, RobotDoesNotSeeItsOwnChassisOrWheels) {
  // The rover's chassis is 0.30 x 0.18 x 0.06 m; its left wheel spans y 0.0975..0.1225 at x = 0.04.
  // A block's -x face at x = 0.9 ahead of it, a wall's face at y = 1.0 to its left.
  const ProjectDesc project = test::project_from_xml(test::project_xml(
      R"(step="0.001")",
      R"(<box name="block" pos="1 0" size="0.2 2 0.5"/><wall name="side" from="-2 1.05" to="2 1.05" height="0.5" thickness="0.1"/>)",
      R"(<robot file="../robots/rover.xml"><pose x="0" y="0" yaw_deg="0"/></robot>)"));
  Simulation sim(project, 1);
  test::run_for(sim, 0.5);  // settle on its wheels and caster
  const Vehicle& rover = sim.robot(0);
  const dBodyID chassis = rover.chassis_body();
  const dReal* p = dBodyGetPosition(chassis);
  const dReal* m = dBodyGetRotation(chassis);
  Eigen::Matrix3d rotation;
  rotation << m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10];
  const Eigen::Vector3d position(p[0], p[1], p[2]);

  // Behind the chassis, looking forward along it.
  const RangeSensor rear(beam_at({-0.3, 0, 0}, 0, 0, 3));
  const RangeReading own = rear.measure(sim.physics(), chassis, -1);
  ASSERT_TRUE(own.hit);
  EXPECT_EQ(own.entity, rover.entity());
  EXPECT_NEAR(own.distance_m, 0.15, 1e-9);  // its rear face, 0.15 m behind the centre
  const RangeReading past = rear.measure(sim.physics(), chassis, rover.entity());
  ASSERT_TRUE(past.hit);
  EXPECT_EQ(past.entity, entity_of(sim.physics(), "block"));
  const Eigen::Vector3d from = position + rotation * Eigen::Vector3d(-0.3, 0, 0);
  const Eigen::Vector3d forward = rotation * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(past.distance_m, (0.9 - from.x()) / forward.x(), 1e-6);

  // Inside the chassis, looking left through the left wheel.
  const RangeSensor left(beam_at({0.04, 0, 0}, 90, 0, 3));
  const RangeReading wheel = left.measure(sim.physics(), chassis, -1);
  ASSERT_TRUE(wheel.hit);
  EXPECT_EQ(wheel.entity, rover.entity());
  EXPECT_LE(wheel.distance_m, 0.0975 + 1e-6);
  const RangeReading wall = left.measure(sim.physics(), chassis, rover.entity());
  ASSERT_TRUE(wall.hit);
  EXPECT_EQ(wall.entity, entity_of(sim.physics(), "side"));
  const Eigen::Vector3d centre = position + rotation * Eigen::Vector3d(0.04, 0, 0);
  const Eigen::Vector3d leftward = rotation * Eigen::Vector3d::UnitY();
  EXPECT_NEAR(wall.distance_m, (1.0 - centre.y()) / leftward.y(), 1e-6);
}

// While the lockstep holds the world still, its sensors share one list of what moves, made at the
// first ask: every reading within the hold is the one a sensor makes alone, and a body moved
// between two holds is seen where it went.
TEST(RangeSensorHits, SensorsHoldingTheWorldStillSeeWhatMovesWhereItIs) {
  // A crate beside the beam, then moved into it: a list kept from before the move would leave it
  // out by its old box.
  const ProjectDesc project = test::project_from_xml(test::project_xml(
      R"(step="0.001")", R"(<box name="crate" pos="1 2" size="0.2 0.2 0.2" mass="1"/>)", ""));
  Simulation sim(project, 1);
  test::run_for(sim, 0.2);  // the crate settles on the ground, its centre 0.1 m up
  dBodyID crate = dGeomGetBody(dSpaceGetGeom(sim.physics().dynamic_space(), 0));
  ASSERT_NE(crate, nullptr);
  const RangeSensor sensor(beam_at({0, 0, 0.1}, 0, 0, 5));
  EXPECT_FALSE(sensor.measure(sim.physics(), nullptr, -1).hit);
  {
    const PhysicsWorld::HoldStill still(sim.physics());
    ASSERT_NE(sim.physics().moving_held_still(), nullptr);
    EXPECT_FALSE(sensor.measure(sim.physics(), nullptr, -1).hit);
    EXPECT_FALSE(sensor.measure(sim.physics(), nullptr, -1).hit);  // from the list
  }
  EXPECT_EQ(sim.physics().moving_held_still(), nullptr);
  const dReal* at = dBodyGetPosition(crate);
  dBodySetPosition(crate, at[0], 0, at[2]);
  const double face = at[0] - 0.1;
  {
    const PhysicsWorld::HoldStill still(sim.physics());
    const RangeReading held = sensor.measure(sim.physics(), nullptr, -1);
    ASSERT_TRUE(held.hit);
    EXPECT_NEAR(held.distance_m, face, 1e-6);
    EXPECT_EQ(held.entity, entity_of(sim.physics(), "crate"));
  }
}

// Where a ray from `origin` first meets a vertical cylinder of radius r about (cx, cy), z 0..height;
// infinity if it does not.
double ray_meets_pole(const Eigen::Vector3d& origin, const Eigen::Vector3d& d, double cx, double cy, double r,
                      double height) {
  const Eigen::Vector2d o(origin.x() - cx, origin.y() - cy), dh(d.x(), d.y());
  const double a = dh.squaredNorm(), b = 2 * o.dot(dh), c = o.squaredNorm() - r * r;
  const double disc = b * b - 4 * a * c;
  if (a == 0 || disc < 0) return INFINITY;
  const double t = (-b - std::sqrt(disc)) / (2 * a);
  const double z = origin.z() + t * d.z();
  return t >= 0 && z >= 0 && z <= height ? t : INFINITY;
}

TEST(RangeSensorHits, ConeBundleSeesAThinPoleOffTheAxisThatTheCentreRayMisses) {
  // A 1 cm pole 0.5 m ahead, 3 degrees left of the axis: it subtends +-1.15 degrees, so the axis
  // ray passes 1.8 degrees wide of it while a 5 degree beam of 1 degree resolution cannot.
  const double cx = 0.5, cy = 0.5 * std::tan(3 * kDeg), r = 0.01, height = 1.0;
  const Scene scene(fmt::format(R"(<tree name="pole" pos="{} {}" trunk_radius="{}" trunk_height="{}" crown_radius="0"/>)",
                                cx, cy, r, height));
  const Eigen::Vector3d origin(0, 0, 0.3);

  const RangeSensor bundle(beam_at(origin, 0, 0, 0.8, 5));
  const RangeReading seen = bundle.measure(scene.physics, nullptr, -1);
  ASSERT_TRUE(seen.hit);
  EXPECT_EQ(seen.entity, entity_of(scene.physics, "pole"));
  EXPECT_NEAR(std::hypot(seen.point_m.x() - cx, seen.point_m.y() - cy), r, 1e-6);  // on its surface
  EXPECT_NEAR((seen.point_m - origin).norm(), seen.distance_m, 1e-9);
  EXPECT_LE(angle_between(seen.point_m - origin, Eigen::Vector3d::UnitX()), 5 * kDeg + 1e-9);
  double expected = INFINITY;
  for (const auto& d : bundle.directions()) expected = std::min(expected, ray_meets_pole(origin, d, cx, cy, r, height));
  EXPECT_NEAR(seen.distance_m, expected, 1e-6);
  EXPECT_GT(seen.distance_m, std::hypot(cx, cy) - r - 1e-9);

  EXPECT_FALSE(RangeSensor(beam_at(origin, 0, 0, 0.8, 0)).measure(scene.physics, nullptr, -1).hit);
  // Turned so the pole sits 8 degrees off the axis, outside the beam, the bundle misses it too.
  EXPECT_FALSE(RangeSensor(beam_at(origin, -5, 0, 0.8, 5)).measure(scene.physics, nullptr, -1).hit);
}

void brute_force_into(dSpaceID space, std::vector<dGeomID>& out) {
  for (int i = 0; i < dSpaceGetNumGeoms(space); ++i) {
    dGeomID g = dSpaceGetGeom(space, i);
    if (dGeomIsSpace(g)) brute_force_into(reinterpret_cast<dSpaceID>(g), out);
    else if (dGeomGetData(g)) out.push_back(g);
  }
}

// The reference: ODE's answer over every tagged geom of the world, static and moving, as a reading.
RangeReading brute_force(const PhysicsWorld& physics, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                         double length, int ignore_entity) {
  std::vector<dGeomID> geoms;
  brute_force_into(physics.static_space(), geoms);
  brute_force_into(physics.dynamic_space(), geoms);
  const RayHit hit = test::ode_closest_hit(geoms, origin, dir, length, ignore_entity);
  RangeReading best;
  best.hit = hit.hit;
  best.distance_m = hit.hit ? hit.distance_m : length;
  best.point_m = hit.point_m;
  best.entity = hit.entity;
  return best;
}

// Random ray origins that meet things often: near the terrain, an obstacle or the rover.
struct RayDraw {
  explicit RayDraw(const DefaultWorld& w) : world(w), random(7) {}
  Eigen::Vector3d origin() {
    const std::vector<Eigen::Vector2d> near = {{0, 0},    {3.5, 0.2}, {1.5, -2.5}, {-2.5, 2}, {-3, -3},
                                               {5, -4},   {2, 3},     {0, 13},     {15, 0},   {-15, -15}};
    const Eigen::Vector3d rover = world.sim.robot(0).state().position_m;
    Eigen::Vector2d xy = uniform(random) < 0.2 ? Eigen::Vector2d(rover.x(), rover.y())
                                               : near[static_cast<std::size_t>(uniform(random) * static_cast<double>(near.size()))];
    xy += Eigen::Vector2d(2 * uniform(random) - 1, 2 * uniform(random) - 1) * 1.5;
    // Above the ground: a ray that starts under a heightfield's surface gets an answer from ODE
    // that depends on the ray's length (where the surface is crossed upwards, or a depth), so there
    // no two ways of asking agree. Sensors start above it.
    const double ground = world.sim.physics().terrain_height(xy.x(), xy.y(), 0.0);
    return {xy.x(), xy.y(), ground + 0.001 + 1.5 * uniform(random) * uniform(random)};
  }
  Eigen::Vector3d direction() {
    // Mostly near level, as rangers and levers look; some steep, some straight up or down.
    const double yaw = 2 * M_PI * uniform(random);
    const double pitch = uniform(random) < 0.8 ? 0.3 * (2 * uniform(random) - 1) : M_PI * (uniform(random) - 0.5);
    return {std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch)};
  }
  double range() { return uniform(random) < 0.5 ? 0.01 + 0.5 * uniform(random) : 0.5 + 20 * uniform(random); }

  const DefaultWorld& world;
  std::mt19937_64 random;
  std::uniform_real_distribution<double> uniform{0.0, 1.0};
};

Eigen::Matrix3d yaw_pitch(const Eigen::Vector3d& dir) {
  return (Eigen::AngleAxisd(std::atan2(dir.y(), dir.x()), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(-std::asin(dir.z()), Eigen::Vector3d::UnitY()))
      .toRotationMatrix();
}

TEST(RangeSensorFastPath, SingleRaysAndBundlesFindWhatEveryGeomTestedAlongEveryRayFinds) {
  const DefaultWorld world(0.3);
  const PhysicsWorld& physics = world.sim.physics();
  const int rover = world.sim.robot(0).entity();
  RayDraw draw(world);
  int hits = 0, misses = 0, terrain = 0, obstacles = 0;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d origin = draw.origin(), dir = draw.direction();
    const double range = draw.range();
    const int ignore = i % 3 == 0 ? rover : -1;
    // The beam is placed in the world by a mount pose that turns +x onto `dir`.
    const RangeSensor sensor(beam_at({0, 0, 0}, 0, 0, range));
    const RangeReading fast = sensor.measure(physics, origin, yaw_pitch(dir), ignore);
    const Eigen::Vector3d axis = yaw_pitch(dir) * sensor.directions()[0];
    const RangeReading slow = brute_force(physics, origin, axis, range, ignore);
    ASSERT_EQ(fast.hit, slow.hit) << i;
    // Both ask ODE's own colliders the same question, the fast path with a ray cut short at the
    // best hit so far: the same contact, to rounding.
    EXPECT_NEAR(fast.distance_m, slow.distance_m, 1e-9) << i;
    EXPECT_EQ(fast.entity, slow.entity) << i;
    (fast.hit ? hits : misses)++;
    if (fast.hit) (fast.entity < 0 ? terrain : obstacles)++;
  }
  // The draw meets every kind of answer often enough for the comparison to mean something.
  EXPECT_GT(hits, 600);
  EXPECT_GT(misses, 600);
  EXPECT_GT(terrain, 200);
  EXPECT_GT(obstacles, 200);

  // Cone bundles: the closest over all their rays, ray by ray through the reference.
  for (int i = 0; i < 150; ++i) {
    const Eigen::Vector3d origin = draw.origin(), dir = draw.direction();
    RangeBeam beam = beam_at({0, 0, 0}, 0, 0, draw.range(), 2 + 10 * draw.uniform(draw.random));
    beam.resolution_rad = 2 * kDeg;
    const RangeSensor sensor(beam);
    const Eigen::Matrix3d mount = yaw_pitch(dir);
    const RangeReading fast = sensor.measure(physics, origin, mount, rover);
    RangeReading slow;
    slow.distance_m = beam.max_range_m;
    for (const auto& d : sensor.directions()) {
      const RangeReading r = brute_force(physics, origin, mount * d, beam.max_range_m, rover);
      if (r.hit && (!slow.hit || r.distance_m < slow.distance_m)) slow = r;
    }
    ASSERT_EQ(fast.hit, slow.hit) << i;
    EXPECT_NEAR(fast.distance_m, slow.distance_m, 1e-9) << i;
  }
}

// Sonar cones (an echo only from a surface struck within max_incidence of its normal): the
// nearest echo over all their rays, each ray's echo decided by its own nearest surface, static or
// moving, through the reference. The draw puts many cones near the crates and the rover, whose
// moving bodies the fast path asks about on every ray, also on those whose static surfaces lie
// beyond an echo already found.
TEST(RangeSensorFastPath, SonarConesEchoFromWhatEveryGeomTestedAlongEveryRayFinds) {
  const DefaultWorld world(0.3);
  const PhysicsWorld& physics = world.sim.physics();
  RayDraw draw(world);
  std::vector<dGeomID> moving_geoms;
  brute_force_into(physics.dynamic_space(), moving_geoms);
  std::vector<int> moving;  // entities
  for (dGeomID g : moving_geoms) moving.push_back(static_cast<const GeomTag*>(dGeomGetData(g))->entity);
  // What a ray sees: a wheel's tread sphere meets only the ground, the ray its tyre.
  std::vector<dGeomID> geoms;
  brute_force_into(physics.static_space(), geoms);
  brute_force_into(physics.dynamic_space(), geoms);
  geoms.erase(std::remove_if(geoms.begin(), geoms.end(),
                             [](dGeomID g) {
                               return static_cast<const GeomTag*>(dGeomGetData(g))->role == GeomRole::Tread;
                             }),
              geoms.end());
  int echoes = 0, from_moving = 0;
  for (int i = 0; i < 240; ++i) {
    Eigen::Vector3d origin = draw.origin(), dir = draw.direction();
    double range = draw.range();
    if (i % 2) {  // at a moving body, from 0.3 to 2.5 m away, a sonar's height above the ground
      const dReal* at = dGeomGetPosition(moving_geoms[static_cast<std::size_t>(i / 2) % moving_geoms.size()]);
      const double away = 0.3 + 2.2 * draw.uniform(draw.random), bearing = 2 * M_PI * draw.uniform(draw.random);
      origin = {at[0] + away * std::cos(bearing), at[1] + away * std::sin(bearing), 0};
      origin.z() = physics.terrain_height(origin.x(), origin.y(), 0.0) + 0.05 + 0.25 * draw.uniform(draw.random);
      dir = (Eigen::Vector3d(at[0], at[1], at[2]) - origin).normalized();
      range = 4.5;
    }
    RangeBeam beam = beam_at({0, 0, 0}, 0, 0, range, 2 + 15 * draw.uniform(draw.random));
    beam.resolution_rad = 2 * kDeg;
    beam.max_incidence_rad = (20 + 50 * draw.uniform(draw.random)) * kDeg;
    const int ignore = i % 4 == 0 ? world.sim.robot(0).entity() : -1;
    const RangeSensor sensor(beam);
    const Eigen::Matrix3d mount = yaw_pitch(dir);
    const RangeReading fast = sensor.measure(physics, origin, mount, ignore);
    RangeReading slow;
    slow.distance_m = beam.max_range_m;
    for (const auto& d : sensor.directions()) {
      const Eigen::Vector3d ray = mount * d;
      const RayHit h = test::ode_closest_hit(geoms, origin, ray, beam.max_range_m, ignore);
      if (!h.hit || std::abs(h.normal_m.dot(ray)) < std::cos(beam.max_incidence_rad)) continue;
      if (!slow.hit || h.distance_m < slow.distance_m) {
        slow.hit = true;
        slow.distance_m = h.distance_m;
        slow.entity = h.entity;
      }
    }
    ASSERT_EQ(fast.hit, slow.hit) << i;
    // The same contacts of ODE's colliders, the fast path's rays cut short at the best so far.
    EXPECT_NEAR(fast.distance_m, slow.distance_m, 1e-9) << i;
    EXPECT_EQ(fast.entity, slow.entity) << i;
    echoes += fast.hit;
    from_moving += fast.hit && std::find(moving.begin(), moving.end(), fast.entity) != moving.end();
  }
  // Enough of each for the comparison to mean something.
  EXPECT_GT(echoes, 100);
  EXPECT_GT(from_moving, 20);
  std::printf("sonar cones: %d echoes, %d from moving bodies\n", echoes, from_moving);
}

// A sonar facing a heightmap ramp rising from x = 2 m, with flat ground below and above it, and
// echoes within 45 degrees of a surface's normal: its nearest echo as the reference (every ray
// through ODE) finds it, the ramp heard and the flat ground alone (looking away) never.
// - A 30-degree ramp under a cone pitched 25 degrees down from 0.3 m, 1.5 m before it: rays more
//   than 30 + 45 degrees from the vertical cannot echo off any cell, so the cone's rays within 15
//   degrees of level are not cast; the ramp still echoes the rays 16 to 30 degrees down (35 to 44
//   degrees off its normal), which are.
// - A 55-degree ramp under a level cone 2 m before it: a level ray meets it 35 degrees off its
//   normal, so no ray may be spared (the terrain's steepest cell leaves no bound).
TEST(RangeSensorFastPath, SonarHearsTerrainTiltedTowardItAndNotGroundItGrazes) {
  struct Case {
    double slope_deg, x0, z0, pitch_deg;
    bool spares;  // whether some of the cone's rays lie beyond the bound
  };
  for (const Case c : {Case{30, 1.5, 0.3, 25, true}, Case{55, 0, 0.3, 0, false}}) {
    const test::TempDir dir;
    const double rise = std::tan(c.slope_deg * kDeg);
    // 81 samples: 0.25 m cells, so that whole cells lie on the ramp.
    const Scene scene(heightmap(dir, "ramp.pgm", 81, 0, 2,
                                [&](double x, double) { return std::clamp((x - 2.0) * rise, 0.0, 1.5); }));
    std::vector<dGeomID> geoms;
    brute_force_into(scene.physics.static_space(), geoms);
    const RayScene& rays = RayScene::of(scene.physics);
    const double grazing = rays.grazing_cos(45 * kDeg);
    for (const double yaw : {0.0, 180.0}) {
      RangeBeam beam = beam_at({c.x0, 0, c.z0}, yaw, c.pitch_deg, 4.5, 15);
      beam.resolution_rad = 2 * kDeg;
      beam.max_incidence_rad = 45 * kDeg;
      const RangeSensor sensor(beam);
      int spared = 0;
      for (const auto& d : sensor.directions()) spared += std::abs(rays.terrain_up().dot(d)) < grazing;
      EXPECT_EQ(spared > 0, c.spares) << c.slope_deg << " deg, " << spared << " rays beyond the bound";
      const RangeReading fast = sensor.measure(scene.physics, nullptr, -1);
      RangeReading slow;
      for (const auto& d : sensor.directions()) {
        const RayHit h = test::ode_closest_hit(geoms, beam.position_m, d, beam.max_range_m, -1);
        if (!h.hit || std::abs(h.normal_m.dot(d)) < std::cos(beam.max_incidence_rad)) continue;
        if (!slow.hit || h.distance_m < slow.distance_m) {
          slow.hit = true;
          slow.distance_m = h.distance_m;
        }
      }
      ASSERT_EQ(slow.hit, yaw == 0) << c.slope_deg << " deg: the reference hears the ramp, not the ground";
      ASSERT_EQ(fast.hit, slow.hit) << c.slope_deg << " deg, yaw " << yaw;
      if (!fast.hit) continue;
      // Beyond the ramp's foot, and the same contact of ODE's heightfield collider to rounding.
      EXPECT_GT(fast.distance_m, 2.0 - c.x0);
      EXPECT_NEAR(fast.distance_m, slow.distance_m, 1e-9) << c.slope_deg << " deg";
    }
  }
}

// A crate that can move, hidden from a level sonar 0.1 m above the ground by a ridge 0.5 m high
// whose 27-degree faces meet every ray of the cone 48 degrees or more off their normals: nothing
// echoes, the crate's square face included, which only a ray through the ridge would reach. With
// a moving body near the beam every ray is cast, as the ground in front of the crate must be
// found to hide it.
TEST(RangeSensorFastPath, GroundThatCannotEchoStillHidesAMovingBodyBehindIt) {
  const test::TempDir dir;
  // 81 samples: 0.25 m cells, so that the ridge's feet and top are samples.
  const Scene scene(heightmap(dir, "ridge.pgm", 81, 0, 1,
                              [](double x, double) { return 0.5 * std::max(0.0, 1.0 - std::abs(x - 2.0)); }) +
                    R"(<box name="crate" pos="3.5 0" size="0.4 0.4 0.4" mass="1"/>)");
  RangeBeam beam = beam_at({0, 0, 0.1}, 0, 0, 4.5, 15);
  beam.resolution_rad = 2 * kDeg;
  beam.max_incidence_rad = 45 * kDeg;
  const RangeSensor sensor(beam);
  std::vector<dGeomID> geoms;
  brute_force_into(scene.physics.static_space(), geoms);
  brute_force_into(scene.physics.dynamic_space(), geoms);
  std::vector<dGeomID> crate;
  brute_force_into(scene.physics.dynamic_space(), crate);
  ASSERT_EQ(crate.size(), 1u);
  int hidden = 0;  // rays that would meet the crate's face were the ridge not there
  for (const auto& d : sensor.directions()) {
    const RayHit h = test::ode_closest_hit(geoms, beam.position_m, d, beam.max_range_m, -1);
    ASSERT_TRUE(!h.hit || std::abs(h.normal_m.dot(d)) < std::cos(beam.max_incidence_rad)) << "no ray echoes";
    hidden += test::ode_closest_hit(crate, beam.position_m, d, beam.max_range_m, -1).hit;
  }
  ASSERT_GT(hidden, 10);
  EXPECT_FALSE(sensor.measure(scene.physics, nullptr, -1).hit);
}

TEST(RangeSensorFastPath, ASetOfBeamsHitsExactlyWhenOneOfItsSensorsDoes) {
  const DefaultWorld world(0.3);
  const PhysicsWorld& physics = world.sim.physics();
  const int rover = world.sim.robot(0).entity();
  RayDraw draw(world);
  int pressed = 0, released = 0;
  for (int i = 0; i < 1500; ++i) {
    // A lever: parallel rays across a width, each a short reach, as the bump switch casts them.
    const double width = 0.05 + 0.3 * draw.uniform(draw.random), reach = 0.005 + 0.3 * draw.uniform(draw.random);
    const int n = static_cast<int>(std::ceil(width / 0.02)) + 1;
    std::vector<RangeBeam> beams;
    for (int k = 0; k < n; ++k)
      beams.push_back(beam_at({0, width * (static_cast<double>(k) / (n - 1) - 0.5), 0}, 0, 0, reach));
    const RangeSensorSet lever(beams);
    const std::vector<RangeSensor>& rays = lever.sensors();
    const Eigen::Vector3d origin = draw.origin();
    const Eigen::Matrix3d mount = yaw_pitch(draw.direction());
    const int ignore = i % 2 ? rover : -1;
    bool any = false, any_reference = false;
    for (const auto& ray : rays) {
      any = any || ray.measure(physics, origin, mount, ignore).hit;
      const Eigen::Vector3d from = origin + mount * ray.beam().position_m;
      any_reference = any_reference || brute_force(physics, from, mount * ray.directions()[0], reach, ignore).hit;
    }
    ASSERT_EQ(any, any_reference) << i;
    ASSERT_EQ(lever.any_hit(physics, origin, mount, ignore), any) << i;
    (any ? pressed : released)++;
  }
  EXPECT_GT(pressed, 100);
  EXPECT_GT(released, 100);

  // Mounted on the rover's chassis, its own bump lever: pressed against a wall, free in the open.
  const Vehicle& v = world.sim.robot(0);
  std::vector<RangeBeam> beams;
  for (int k = 0; k <= 9; ++k) beams.push_back(beam_at({0.14, 0.18 * (k / 9.0 - 0.5), -0.01}, 0, 0, 0.02));
  const RangeSensorSet lever(beams);
  const std::vector<RangeSensor>& rays = lever.sensors();
  EXPECT_FALSE(lever.any_hit(physics, v.chassis_body(), rover));  // the rover starts in the open
  EXPECT_TRUE(lever.any_hit(physics, v.chassis_body(), -1) ==
              std::any_of(rays.begin(), rays.end(),
                          [&](const RangeSensor& r) { return r.measure(physics, v.chassis_body(), -1).hit; }));
}

}  // namespace
}  // namespace sear
