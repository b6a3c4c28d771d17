// The static world's BVH (sensors/ray_scene) against ODE's own colliders on thousands of random
// rays in the default world; specular loss of a sonar beam at a grazing wall; a LIDAR fan against
// the exact geometry of a wall and a box corner; the scene is built once and shared.
#include "sensors/ray_scene.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "physics/physics_world.hpp"
#include "ray_fixture.hpp"
#include "sensors/range_sensor.hpp"

namespace sear {
namespace {

constexpr double kDeg = M_PI / 180.0;
// One unit in the last place of a float, relative: Embree holds origins, directions and vertices so.
constexpr double kFloatEps = 1.0 / (1 << 24);

using test::DefaultWorld;
using test::entity_of;
using test::Scene;

// The reference: ODE's answer over every geom of the static space, which is what the scene holds.
RayHit ode_reference(const PhysicsWorld& physics, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                     double length, int ignore_entity) {
  std::vector<dGeomID> geoms;
  for (int i = 0; i < dSpaceGetNumGeoms(physics.static_space()); ++i)
    geoms.push_back(dSpaceGetGeom(physics.static_space(), i));
  return test::ode_closest_hit(geoms, origin, dir, length, ignore_entity);
}

// The angle between a ray and a surface normal, from either side: pi/2 is grazing.
double incidence(const Eigen::Vector3d& dir, const Eigen::Vector3d& normal) {
  return std::acos(std::min(1.0, std::abs(dir.dot(normal.normalized()))));
}

TEST(RayScene, AgreesWithOdeOnThousandsOfRandomRaysInTheDefaultWorld) {
  const DefaultWorld world(0.2);
  const PhysicsWorld& physics = world.sim.physics();
  const RayScene& scene = RayScene::of(physics);
  // The 129 x 129 heightmap as ODE's 2 x 128 x 128 triangles, the rock's, and 12 per fixed box.
  EXPECT_GE(scene.triangle_count(), 2u * 128 * 128);
  EXPECT_TRUE(scene.ode_only().empty());

  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const std::vector<Eigen::Vector2d> near = {{0, 0},  {3.5, 0.2}, {-2.5, 2}, {-3, -3}, {5, -4},
                                             {2, 3},  {0, 12.5},  {14.5, 0}, {-12, -12}};
  int hits = 0, misses = 0, terrain = 0, obstacles = 0, float_checked = 0;
  for (int i = 0; i < 4000; ++i) {
    Eigen::Vector2d xy = near[static_cast<std::size_t>(uniform(random) * static_cast<double>(near.size()))];
    xy += Eigen::Vector2d(2 * uniform(random) - 1, 2 * uniform(random) - 1) * 2.0;
    // Above the ground, as sensors are: under a heightfield ODE's answer depends on the ray's length.
    const double ground = physics.terrain_height(xy.x(), xy.y(), 0.0);
    const Eigen::Vector3d origin(xy.x(), xy.y(), ground + 0.002 + 1.5 * uniform(random) * uniform(random));
    const double yaw = 2 * M_PI * uniform(random);
    const double pitch = uniform(random) < 0.8 ? 0.3 * (2 * uniform(random) - 1) : M_PI * (uniform(random) - 0.5);
    const Eigen::Vector3d dir(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
    const double range = uniform(random) < 0.3 ? 0.02 + 1.5 * uniform(random) : 1.5 + 12 * uniform(random);
    const int ignore = i % 4 == 0 ? entity_of(physics, "crate") : -1;

    const RayHit slow = ode_reference(physics, origin, dir, range, ignore);
    const RayHit fast = scene.nearest(origin, dir, range, ignore);
    ASSERT_EQ(fast.hit, slow.hit) << i;
    (slow.hit ? hits : misses)++;
    if (!slow.hit) continue;
    (slow.entity < 0 ? terrain : obstacles)++;
    // Refined: the same plane or the same ODE collider, so the same figure to double rounding
    // (1e-9 m is a millionth of a millimetre, and a few thousand ulps of 20 m).
    EXPECT_NEAR(fast.distance_m, slow.distance_m, 1e-9) << i;
    EXPECT_EQ(fast.entity, slow.entity) << i;
    EXPECT_NEAR((fast.point_m - slow.point_m).norm(), 0.0, 1e-9) << i;
    EXPECT_NEAR(std::abs(fast.normal_m.dot(slow.normal_m)), 1.0, 1e-9) << i;
    EXPECT_LE(fast.normal_m.dot(dir), 0.0) << i;  // turned to face the sensor

    // Embree's own float figure, unrefined: off by the float rounding of origin, direction and
    // vertices (each within 2^-24 of |o| + t across the ray), ten such roundings to be safe, seen
    // along the ray through 1 / cos(incidence). Grazing rays (over 85 degrees) are left out.
    const double inc = incidence(dir, slow.normal_m);
    if (inc > 85 * kDeg || slow.distance_m > range - 1e-3) continue;
    BvhHit raw;
    scene.cast(&origin, true, &dir, 1, range, ignore, &raw);
    ASSERT_TRUE(std::isfinite(raw.t)) << i;
    EXPECT_NEAR(raw.t, slow.distance_m, 10 * kFloatEps * (origin.norm() + slow.distance_m) / std::cos(inc)) << i;
    ++float_checked;
  }
  // Every kind of answer came up often enough for the agreement to mean something.
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, 600);
  EXPECT_GT(terrain, 400);
  EXPECT_GT(obstacles, 200);
  EXPECT_GT(float_checked, 900);
}

TEST(RayScene, BuiltOncePerWorldAndSharedUntilTheStaticSpaceGrows) {
  Scene scene(R"(<box name="crate" pos="2 0" size="0.4 3 1"/>)");
  const RayScene& first = RayScene::of(scene.physics);
  EXPECT_EQ(&RayScene::of(scene.physics), &first);
  RangeBeam beam;
  beam.position_m = {0, 0, 0.3};
  beam.max_range_m = 5;
  const RangeSensor a(beam), b(beam);
  EXPECT_NEAR(a.measure(scene.physics, nullptr, -1).distance_m, 1.8, 1e-9);
  EXPECT_NEAR(b.measure(scene.physics, nullptr, -1).distance_m, 1.8, 1e-9);
  EXPECT_EQ(&RayScene::of(scene.physics), &first);
  // A static box added after the first cast is seen: the scene is built again.
  dGeomID wall = dCreateBox(scene.physics.static_space(), 0.2, 3, 1);
  dGeomSetPosition(wall, 1.1, 0, 0.5);
  scene.physics.tag(wall, GeomRole::Obstacle, scene.physics.add_entity("late"), 0);
  const RangeReading r = a.measure(scene.physics, nullptr, -1);
  EXPECT_NEAR(r.distance_m, 1.0, 1e-9);
  EXPECT_EQ(r.entity, entity_of(scene.physics, "late"));
  // A static obstacle of the ignored entity is not seen, by the BVH's filter as by ODE.
  EXPECT_NEAR(a.measure(scene.physics, nullptr, entity_of(scene.physics, "late")).distance_m, 1.8, 1e-9);
}

// A static crate whose -x face is the plane x = 1.8, a dynamic parcel whose +x face is x = -1.8
// (|y| <= 0.2, z 0..0.4).
RangeBeam sonar_at(const Eigen::Vector3d& position, double yaw_deg, double half_angle_deg, double max_incidence_deg) {
  RangeBeam beam;
  beam.position_m = position;
  beam.yaw_rad = yaw_deg * kDeg;
  beam.half_angle_rad = half_angle_deg * kDeg;
  beam.resolution_rad = 2 * kDeg;
  beam.max_range_m = 6;
  beam.max_incidence_rad = max_incidence_deg * kDeg;
  return beam;
}

TEST(RangeSensorSpecular, AWallStruckAt20DegreesEchoesAt70DoesNotWithMaxIncidence45) {
  // The crate 12 m wide here (|y| <= 6): a ray at 70 degrees meets its face at y = 1.8 tan 70 = 4.9.
  const Scene scene(R"(<box name="crate" pos="2 0" size="0.4 12 1"/><box name="parcel" pos="-2 0" size="0.4 0.4 0.4" mass="1"/>)");
  const Eigen::Vector3d origin(0, 0, 0.3);
  // The crate's face, normal -x: a ray at yaw psi meets it at incidence psi, 1.8 / cos(psi) away.
  const RangeReading at20 = RangeSensor(sonar_at(origin, 20, 0, 45)).measure(scene.physics, nullptr, -1);
  ASSERT_TRUE(at20.hit);
  EXPECT_NEAR(at20.distance_m, 1.8 / std::cos(20 * kDeg), 1e-9);
  EXPECT_NEAR((at20.normal_m - Eigen::Vector3d(-1, 0, 0)).norm(), 0.0, 1e-9);
  EXPECT_FALSE(RangeSensor(sonar_at(origin, 70, 0, 45)).measure(scene.physics, nullptr, -1).hit);
  // Without the limit the same ray is seen, 1.8 / cos 70 = 5.26 m away.
  const RangeReading plain = RangeSensor(sonar_at(origin, 70, 0, 90)).measure(scene.physics, nullptr, -1);
  ASSERT_TRUE(plain.hit);
  EXPECT_NEAR(plain.distance_m, 1.8 / std::cos(70 * kDeg), 1e-9);
  // Either side of 45 degrees, by a degree.
  EXPECT_TRUE(RangeSensor(sonar_at(origin, 44, 0, 45)).measure(scene.physics, nullptr, -1).hit);
  EXPECT_FALSE(RangeSensor(sonar_at(origin, 46, 0, 45)).measure(scene.physics, nullptr, -1).hit);

  // A 10 degree beam at yaw 70: its rays meet the face at 60..80 degrees, all past 45: silent.
  EXPECT_FALSE(RangeSensor(sonar_at(origin, 70, 10, 45)).measure(scene.physics, nullptr, -1).hit);
  // At yaw 40 its rays span 30..50 degrees: the echo comes from the nearest ray within 45, the
  // one struck most squarely, at 30 degrees: 1.8 / cos 30.
  const RangeReading wide = RangeSensor(sonar_at(origin, 40, 10, 45)).measure(scene.physics, nullptr, -1);
  ASSERT_TRUE(wide.hit);
  EXPECT_NEAR(wide.distance_m, 1.8 / std::cos(30 * kDeg), 1e-6);

  // ODE alone (the reference path) hears the same echoes.
  for (double yaw : {20.0, 44.0, 46.0, 70.0}) {
    for (double half_angle : {0.0, 10.0}) {
      const RangeSensor s(sonar_at(origin, yaw, half_angle, 45));
      const RangeReading fast = s.measure(scene.physics, nullptr, -1);
      const RangeReading slow = s.measure_ode_only(scene.physics, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), -1);
      ASSERT_EQ(fast.hit, slow.hit) << yaw << " " << half_angle;
      EXPECT_NEAR(fast.distance_m, slow.distance_m, 1e-9) << yaw << " " << half_angle;
    }
  }

  // A body that moves (the parcel, through ODE) loses its echo the same way.
  const int parcel = entity_of(scene.physics, "parcel");
  const RangeReading square = RangeSensor(sonar_at(origin, 180 + 5, 0, 45)).measure(scene.physics, nullptr, -1);
  ASSERT_TRUE(square.hit);
  EXPECT_EQ(square.entity, parcel);
  EXPECT_NEAR(square.distance_m, 1.8 / std::cos(5 * kDeg), 1e-9);
  EXPECT_NEAR(std::abs(square.normal_m.x()), 1.0, 1e-9);
  // Its +y side (y = 0.2, x -2.2..-1.8) from (-2.15, 0.3): yaw -30 degrees meets it after
  // 0.1 / sin 30 = 0.2 m at x = -1.977, 60 degrees off its normal: silent.
  RangeBeam side = sonar_at({-2.15, 0.3, 0.2}, -30, 0, 45);
  EXPECT_FALSE(RangeSensor(side).measure(scene.physics, nullptr, -1).hit);
  side.max_incidence_rad = 90 * kDeg;
  const RangeReading oblique = RangeSensor(side).measure(scene.physics, nullptr, -1);
  ASSERT_TRUE(oblique.hit);
  EXPECT_NEAR(oblique.distance_m, 0.1 / std::cos(60 * kDeg), 1e-9);
  EXPECT_EQ(oblique.entity, parcel);
  side.max_incidence_rad = 45 * kDeg;
  side.yaw_rad = -90 * kDeg;  // square on, 0.1 m
  const RangeReading down = RangeSensor(side).measure(scene.physics, nullptr, -1);
  ASSERT_TRUE(down.hit);
  EXPECT_NEAR(down.distance_m, 0.1, 1e-9);
}

// Where a level ray from `o` along `d` first meets a vertical rectangle's sides (centre c, yaw,
// half sides hx, hy) in the plane: the exact geometry; INFINITY for none. Slab test in its frame.
double ray_meets_rectangle(const Eigen::Vector2d& o, const Eigen::Vector2d& d, const Eigen::Vector2d& c, double yaw,
                           double hx, double hy, Eigen::Vector2d* normal = nullptr) {
  const Eigen::Rotation2Dd to_box(-yaw);
  const Eigen::Vector2d lo = to_box * (o - c), ld = to_box * d;
  double enter = -INFINITY, leave = INFINITY;
  int axis_in = -1;
  const double half[2] = {hx, hy};
  for (int axis = 0; axis < 2; ++axis) {
    if (ld[axis] == 0) {
      if (std::abs(lo[axis]) > half[axis]) return INFINITY;
      continue;
    }
    double t0 = (-half[axis] - lo[axis]) / ld[axis], t1 = (half[axis] - lo[axis]) / ld[axis];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > enter) {
      enter = t0;
      axis_in = axis;
    }
    leave = std::min(leave, t1);
  }
  if (enter > leave || enter < 0) return INFINITY;
  if (normal) {
    Eigen::Vector2d n(0, 0);
    n[axis_in] = 1;
    *normal = Eigen::Rotation2Dd(yaw) * n;
  }
  return enter;
}

TEST(RangeScanFan, AWallAndABoxCornerAtTheirExactDistances) {
  // A wall along the line 4 m from the scanner, turned so its normal points 25 degrees off the
  // scanner's heading; a box turned 45 degrees with a corner towards it on the right; a loose
  // parcel (a body, through ODE) to the left, 10 degrees behind abeam. Flat ground; the rays run level 0.3 m up.
  const Eigen::Vector2d scanner(1, -0.5);
  const double heading = 30 * kDeg;  // the mount's yaw
  const double wall_normal = heading + 25 * kDeg;
  const Eigen::Vector2d n(std::cos(wall_normal), std::sin(wall_normal)), along(-n.y(), n.x());
  const double centre_line = 4.0, thickness = 0.1;
  const Eigen::Vector2d mid = scanner + centre_line * n;
  const Eigen::Vector2d from = mid - 6 * along, to = mid + 6 * along;
  const Eigen::Vector2d box_centre = scanner + 2.5 * Eigen::Vector2d(std::cos(heading - 60 * kDeg), std::sin(heading - 60 * kDeg));
  const double box_yaw = heading - 60 * kDeg + 45 * kDeg;
  const Eigen::Vector2d parcel_centre = scanner + 1.5 * Eigen::Vector2d(std::cos(heading + 100 * kDeg), std::sin(heading + 100 * kDeg));
  const Scene scene(fmt::format(
      R"(<wall name="wall" from="{} {}" to="{} {}" height="1" thickness="{}"/>)"
      R"(<box name="block" pos="{} {}" size="0.6 0.6 1" yaw_deg="{}"/>)"
      R"(<box name="parcel" pos="{} {}" size="0.4 0.4 0.6" mass="1" yaw_deg="10"/>)",
      from.x(), from.y(), to.x(), to.y(), thickness, box_centre.x(), box_centre.y(), box_yaw / kDeg,
      parcel_centre.x(), parcel_centre.y()));

  ScanFan fan;
  fan.position_m = {0.1, 0, 0.3};  // on the mount, 10 cm ahead of its origin
  fan.first_angle_rad = -30 * kDeg;
  fan.step_rad = 0.25 * kDeg;
  fan.count = 961;  // -30 .. 210 degrees
  fan.max_range_m = 8;
  const RangeScan scan(fan);
  const Eigen::Matrix3d mount = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d mount_at(scanner.x() - 0.1 * std::cos(heading), scanner.y() - 0.1 * std::sin(heading), 0);
  std::vector<float> d(static_cast<std::size_t>(fan.count));
  scan.scan(scene.physics, mount_at, mount, -1, d.data());

  // Angle 0 is the mount's right, pi/2 straight ahead.
  EXPECT_NEAR((scan.direction(0) - Eigen::Vector3d(std::sin(-30 * kDeg), -std::cos(-30 * kDeg), 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((scan.direction(480) - Eigen::Vector3d(1, 0, 0)).norm(), 0, 1e-12);

  int wall_rays = 0, box_rays = 0, parcel_rays = 0, empty_rays = 0;
  const double face = centre_line - 0.5 * thickness;
  for (int i = 0; i < fan.count; ++i) {
    const Eigen::Vector3d dir3 = mount * scan.direction(i);
    const Eigen::Vector2d dir(dir3.x(), dir3.y());
    // The wall's face: d / cos(angle off its normal), within its 12 m length.
    double expected = INFINITY, off_normal = 0;
    bool near_edge = false;
    const double cos_off = dir.dot(n);
    if (cos_off > 0) {
      const double t = face / cos_off;
      const double s = (scanner + t * dir - mid).dot(along);
      near_edge = std::abs(std::abs(s) - 6) < 1e-3;
      if (std::abs(s) <= 6 && t <= fan.max_range_m) {
        expected = t;
        off_normal = std::acos(cos_off);
      }
    }
    Eigen::Vector2d box_normal(0, 0);
    const double tb = ray_meets_rectangle(scanner, dir, box_centre, box_yaw, 0.3, 0.3, &box_normal);
    // The box's silhouette corners are where a ray flips from hit to miss: left out.
    for (double sx : {-0.3, 0.3})
      for (double sy : {-0.3, 0.3}) {
        const Eigen::Vector2d corner = box_centre + Eigen::Rotation2Dd(box_yaw) * Eigen::Vector2d(sx, sy) - scanner;
        near_edge = near_edge || std::abs(std::atan2(dir.x() * corner.y() - dir.y() * corner.x(), dir.dot(corner))) < 1e-4;
      }
    bool box = false;
    if (tb < expected) {
      expected = tb;
      off_normal = std::acos(std::min(1.0, std::abs(dir.dot(box_normal))));
      box = true;
    }
    const double tp = ray_meets_rectangle(scanner, dir, parcel_centre, 10 * kDeg, 0.2, 0.2);
    if (near_edge) continue;
    if (tp < expected) {
      // A body through ODE: its figure is ODE's, in double, then stored as a float.
      ASSERT_TRUE(std::isfinite(d[static_cast<std::size_t>(i)])) << i;
      EXPECT_NEAR(d[static_cast<std::size_t>(i)], tp, 2 * kFloatEps * tp + 1e-9) << i;
      ++parcel_rays;
      continue;
    }
    if (!std::isfinite(expected)) {
      EXPECT_TRUE(std::isinf(d[static_cast<std::size_t>(i)])) << i << " " << d[static_cast<std::size_t>(i)];
      ++empty_rays;
      continue;
    }
    if (off_normal > 80 * kDeg) continue;  // grazing: the hit point is ill-conditioned along the ray
    // Embree's float rounding of the origin (|o| ~ 1.1 m), the direction and the vertices (~ 6 m
    // from the world's origin), each 2^-24 of its size across the ray, ten such, along the ray
    // through 1 / cos(angle off the normal).
    const double tol = 10 * kFloatEps * (6.0 + expected) / std::cos(off_normal);
    ASSERT_TRUE(std::isfinite(d[static_cast<std::size_t>(i)])) << i;
    EXPECT_NEAR(d[static_cast<std::size_t>(i)], expected, tol) << i;
    (box ? box_rays : wall_rays)++;
  }
  EXPECT_GT(wall_rays, 200);
  EXPECT_GT(box_rays, 20);
  EXPECT_GT(parcel_rays, 20);
  EXPECT_GT(empty_rays, 100);

  // The wall straight along its normal (angle 90 + 25 degrees): exactly its face distance.
  const int square = 480 + 100;
  EXPECT_NEAR(d[square], face, 10 * kFloatEps * (6.0 + face));

  // The same rays through ODE alone agree within the float tolerance everywhere but at edges.
  std::vector<float> reference(d.size());
  scan.scan_ode_only(scene.physics, mount_at, mount, -1, reference.data());
  int agree = 0;
  for (std::size_t i = 0; i < d.size(); ++i)
    agree += (std::isinf(d[i]) && std::isinf(reference[i])) || std::abs(d[i] - reference[i]) < 1e-4;
  EXPECT_GE(agree, fan.count - 2);

  // The same fan swept the other way (first 210 degrees, step -0.25) gives the same rays in
  // reverse order, the parcel's included.
  ScanFan reverse = fan;
  reverse.first_angle_rad = 210 * kDeg;
  reverse.step_rad = -0.25 * kDeg;
  std::vector<float> back(d.size());
  RangeScan(reverse).scan(scene.physics, mount_at, mount, -1, back.data());
  for (std::size_t i = 0; i < d.size(); ++i)
    EXPECT_TRUE(back[d.size() - 1 - i] == d[i] || std::abs(back[d.size() - 1 - i] - d[i]) < 1e-5f) << i;

  // Ignoring the block lets the rays that met it run on to the wall or out of range.
  std::vector<float> past(d.size());
  scan.scan(scene.physics, mount_at, mount, entity_of(scene.physics, "block"), past.data());
  int longer = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    EXPECT_GE(past[i], d[i]) << i;
    longer += past[i] > d[i] + 0.01f;
  }
  EXPECT_GE(longer, box_rays);
}

}  // namespace
}  // namespace sear
