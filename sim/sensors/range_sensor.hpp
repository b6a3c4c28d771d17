// Range sensing against the one world: a single ray, the nested-cone bundle SEAR uses for sensors
// with a beam width (IR rangers, sonar), and a LIDAR's planar fan. The static scenery is asked
// through its BVH (sensors/ray_scene), the bodies that move through ODE; the nearer hit wins. It
// reports the true distance; device models decide what the sensor outputs for it.
// Frames: robot x forward, y left, z up; world x east, y north, z up.
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "physics/physics_world.hpp"
#include "scene/description.hpp"
#include "sensors/ray_scene.hpp"

namespace sear {

// Where a beam is mounted and how wide it is. Mounted on a body (a robot's chassis) the pose is in
// that body's frame; with no body the same numbers place the sensor in the world frame.
struct RangeBeam {
  Eigen::Vector3d position_m{0, 0, 0};  // where the rays start
  double yaw_rad = 0;                   // counter-clockwise about z from x
  // About the yawed y axis: positive tilts the beam down, as in the Z-Y-X angles of VehicleState.
  double pitch_rad = 0;
  double half_angle_rad = 0;  // alpha, the beam's half-width; 0: a single ray
  // delta: neighbouring rays are at most this far apart, so every direction in the beam lies
  // within about 0.7 delta of a ray.
  double resolution_rad = 1.0 * kDegToRad;
  double min_range_m = 0;  // closer hits are still reported, flagged below_min
  double max_range_m = 1;
  // Specular loss (sonar): a ray striking a surface more obliquely than this, the angle between
  // the ray and the surface normal from either side, sends no echo back, and that ray sees nothing
  // (the surface still blocks it). 90 degrees: every surface echoes.
  double max_incidence_rad = 90 * kDegToRad;
};

struct RangeReading {
  bool hit = false;  // a surface lies within [0, max_range_m] along some ray
  // Hit closer than min_range_m. distance_m is still the true distance: what a device outputs there
  // is the device model's business (a Sharp GP2D12's voltage falls again below 10 cm).
  bool below_min = false;
  double distance_m = 0;             // along the ray that hit closest; max_range_m when nothing is hit
  Eigen::Vector3d point_m{0, 0, 0};  // world frame, the closest hit; meaningless without one
  int entity = -1;                   // what was hit (PhysicsWorld::entity_names()), -1 the terrain
  Eigen::Vector3d normal_m{0, 0, 0};  // world frame, unit, at point_m, facing the sensor; meaningless without a hit
};

namespace detail {
// A geom asked through ODE, with its box (ODE's order: min x, max x, min y, max y, min z, max z).
struct RayCandidate {
  dGeomID geom;
  int entity;
  double aabb[6];
};
struct RayDeleter {
  void operator()(dGeomID ray) const;
};
}  // namespace detail

// The rays of one beam and a reusable ODE ray to cast them with. The rays are the beam axis, then
// cones of half-angle alpha, alpha - delta, alpha - 2 delta, ... while above zero, each carrying
// rays_on_cone() rays evenly spaced around it starting from its left-most (mount +y side) ray.
// The closest hit over all rays wins: a narrow pole anywhere in the beam is seen, as a real ranger
// with a wide beam sees it, where the axis ray alone would pass it by.
//
// A ray sees every tagged geom in the world's static and dynamic spaces from either side (no
// backface culling: meshes whose winding is inconsistent still block it), except those of
// `ignore_entity`, the robot carrying the sensor. A ray that starts inside a box or sphere reports
// where it leaves it, as ODE does. The rays are cast through the world's RayScene 16 at a time;
// the ray that decides the reading is re-asked of ODE for the geom it struck, so distances are
// ODE's to rounding (see RayScene). measure() reuses scratch memory and the world's collision
// data: call it from the thread that steps the world, one call at a time per sensor.
class RangeScan;

class RangeSensor {
 public:
  // Throws std::invalid_argument for a half-angle outside [0, 90) degrees, a resolution <= 0,
  // ranges out of order, a max incidence outside (0, 90] degrees, or more than kMaxRays rays.
  explicit RangeSensor(const RangeBeam& beam);

  static constexpr std::size_t kMaxRays = 100000;  // a typo in a resolution should not stall a run

  // Rays on a cone of half-angle theta: the fewest, but at least 3, such that neighbouring rays are
  // at most delta apart, max(3, ceil(pi / asin(sin(delta / 2) / sin(theta)))). For small angles
  // that is about 2 pi theta / delta; where sin(theta) <= sin(delta / 2) it is 3.
  static int rays_on_cone(double theta_rad, double resolution_rad);
  // Every ray of a beam of this half-angle and resolution, the axis included, exact up to a
  // million; beyond, some number above a million. The constructor refuses beams of more than
  // kMaxRays, and so can a project's loader before any world exists.
  static double ray_count(double half_angle_rad, double resolution_rad);

  const RangeBeam& beam() const { return beam_; }
  // Unit ray directions in the mount frame (yaw and pitch applied); the first is the beam axis.
  const std::vector<Eigen::Vector3d>& directions() const { return directions_; }

  // The beam mounted on `mount_body` (its frame is the robot frame), or placed in the world when
  // that is nullptr. `ignore_entity` is the robot's own entity; a negative one ignores nothing
  // (the terrain, entity -1, is always seen).
  RangeReading measure(const PhysicsWorld& physics, dBodyID mount_body, int ignore_entity) const;
  // The same with the mount's pose in the world given directly (a sensor on a pan servo).
  RangeReading measure(const PhysicsWorld& physics, const Eigen::Vector3d& mount_position_m,
                       const Eigen::Matrix3d& mount_rotation, int ignore_entity) const;
  // The same through ODE alone, every ray against every geom of both spaces whose box it meets:
  // the path before the BVH, kept as the reference for tests and benchmarks.
  RangeReading measure_ode_only(const PhysicsWorld& physics, const Eigen::Vector3d& mount_position_m,
                                const Eigen::Matrix3d& mount_rotation, int ignore_entity) const;

 private:
  friend class RangeSensorSet;
  friend class RangeScan;
  using Candidate = detail::RayCandidate;

  // Turns the rays into the world for this mount and widens `bounds` (ODE's AABB order) to hold
  // every ray from its origin to its max range; returns the origin.
  Eigen::Vector3d place(const Eigen::Vector3d& mount_position_m, const Eigen::Matrix3d& mount_rotation,
                        double bounds[6]) const;
  // Every tagged geom of `space` (and the spaces in it) whose box meets `bounds`, but those of
  // `ignore_entity`, appended to `out` in the space's order.
  static void gather(dSpaceID space, const double bounds[6], int ignore_entity, std::vector<Candidate>& out);
  // The same for the dynamic space, from the list a HoldStill keeps (PhysicsWorld) when one does.
  static void gather_moving(const PhysicsWorld& physics, const double bounds[6], int ignore_entity,
                            std::vector<Candidate>& out);
  // The closest hit of the placed rays among `candidates`, nearer than `reading` (a hit already
  // found, or none with distance_m the max range); with `first_hit_will_do` it stops at the first
  // hit it finds, which then need not be the closest.
  RangeReading cast(const Eigen::Vector3d& origin, const std::vector<Candidate>& candidates, bool first_hit_will_do,
                    RangeReading reading) const;
  // The nearest static hit over the placed rays, exact (refined), as a reading.
  RangeReading nearest_static(const RayScene& scene, const Eigen::Vector3d& origin, int ignore_entity) const;
  // With a max incidence: each ray's own nearest hit, kept only if it echoes. `bounds`: place()'s.
  RangeReading nearest_echo(const RayScene& scene, const Eigen::Vector3d& origin, const double bounds[6],
                            const std::vector<Candidate>& candidates, int ignore_entity) const;
  dGeomID ray() const;

  RangeBeam beam_;
  std::vector<Eigen::Vector3d> directions_;
  // Created on first use, when a PhysicsWorld exists and so ODE is initialised; in no space.
  mutable std::unique_ptr<dxGeom, detail::RayDeleter> ray_;
  mutable std::vector<Eigen::Vector3d> world_directions_;  // per call, sized once
  mutable std::vector<Candidate> candidates_;              // geoms near the beam, per call
  mutable std::vector<BvhHit> bvh_hits_;                   // per call, sized once
  mutable std::vector<std::uint32_t> ray_order_;           // per call: rays nearest surface first
  mutable std::vector<std::array<double, 6>> near_boxes_;  // per call: RayScene::others_near()
  mutable std::vector<std::uint32_t> cast_rays_;           // per call: the rays that may echo
  mutable std::vector<Eigen::Vector3d> cast_dirs_;         // and their directions
  mutable std::vector<BvhHit> cast_hits_;                  // and Embree's hits
};

// Beams on one mount that are asked together whether any of them touches something: a bump
// lever's parallel rays. One pass over the world's geoms gathers what lies near all of them, where
// each RangeSensor::measure() would make its own pass (a lever of ten rays walked every geom of the
// world ten times a step, and with every robot's parts in it that grows with the square of the
// number of robots); the rays then meet exactly the geoms and hits they would meet one by one.
class RangeSensorSet {
 public:
  explicit RangeSensorSet(std::vector<RangeSensor> sensors);
  // Throws as RangeSensor's constructor does for any of the beams.
  explicit RangeSensorSet(const std::vector<RangeBeam>& beams);

  const std::vector<RangeSensor>& sensors() const { return sensors_; }

  // True exactly when measure(physics, mount_body, ignore_entity).hit is true for some sensor:
  // a surface lies within [0, max range] of one of the rays. Stops at the first ray that hits.
  bool any_hit(const PhysicsWorld& physics, dBodyID mount_body, int ignore_entity) const;
  bool any_hit(const PhysicsWorld& physics, const Eigen::Vector3d& mount_position_m,
               const Eigen::Matrix3d& mount_rotation, int ignore_entity) const;

 private:
  std::vector<RangeSensor> sensors_;
  mutable std::vector<Eigen::Vector3d> origins_;                // per call, one per sensor
  mutable std::vector<RangeSensor::Candidate> candidates_;      // geoms near any beam, per call
  mutable std::vector<Eigen::Vector3d> ray_origins_, ray_directions_;  // every sensor's rays, per call
  mutable std::vector<double> reach_;                                  // their max ranges
  mutable std::vector<BvhHit> bvh_hits_;
};

// A LIDAR's fan of rays in the mount's horizontal (x-y) plane. Angles count counter-clockwise seen
// from above, from the mount's right: 0 along -y, pi/2 straight ahead (+x), pi along +y.
struct ScanFan {
  Eigen::Vector3d position_m{0, 0, 0};  // where the rays start, in the mount frame
  double first_angle_rad = 0;
  double step_rad = 0.5 * kDegToRad;
  int count = 361;
  double max_range_m = 8;
};

// Casts a fan against the one world: the static scenery through its BVH in packets of 16, the
// bodies that move through ODE (each only for the rays whose path its box meets). Distances are
// Embree's float figures, within RayScene::float_slack_m() of ODE's; a moving body's are ODE's.
// Call it from the thread that steps the world, one call at a time per scan.
class RangeScan {
 public:
  // Throws std::invalid_argument for a count outside [1, 100000], a max range <= 0, or a
  // non-finite angle.
  explicit RangeScan(const ScanFan& fan);

  const ScanFan& fan() const { return fan_; }
  // Unit ray directions in the mount frame.
  Eigen::Vector3d direction(int i) const;

  // distances_m[0 .. count): the distance to the nearest surface along each ray, INFINITY where
  // none lies within max range. The mount as in RangeSensor::measure().
  void scan(const PhysicsWorld& physics, dBodyID mount_body, int ignore_entity, float* distances_m) const;
  void scan(const PhysicsWorld& physics, const Eigen::Vector3d& mount_position_m,
            const Eigen::Matrix3d& mount_rotation, int ignore_entity, float* distances_m) const;
  // The same rays through ODE alone, every geom of both spaces: the old path, for comparison.
  void scan_ode_only(const PhysicsWorld& physics, const Eigen::Vector3d& mount_position_m,
                     const Eigen::Matrix3d& mount_rotation, int ignore_entity, float* distances_m) const;

 private:
  ScanFan fan_;
  std::vector<float> cos_, sin_;  // per ray: the direction is cos (mount -y) + sin (mount +x)
  mutable std::unique_ptr<dxGeom, detail::RayDeleter> ray_;
  mutable std::vector<RangeSensor::Candidate> candidates_;
};

}  // namespace sear
