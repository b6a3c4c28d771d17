#include "sensors/range_sensor.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace sear {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

// A heightfield reports every terrain cell plane a ray crosses, unsorted; room for a ray skimming
// many hills. Other geoms report at most one contact per ray.
constexpr int kMaxContacts = 32;

// Leaves room for rounding in ODE's boxes and in the slab test, so that no true hit is culled.
constexpr double kAabbSlack_m = 1e-6;

// Whether the segment origin + t dir, t in [0, length], meets the box; the cheap test that spares
// the exact collider most rays. Infinite bounds (a plane's) work: no 0 * inf arises.
bool segment_meets_box(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double length,
                       const double aabb[6]) {
  double enter = 0, leave = length;
  for (int axis = 0; axis < 3; ++axis) {
    const double lo = aabb[2 * axis] - kAabbSlack_m, hi = aabb[2 * axis + 1] + kAabbSlack_m;
    const double o = origin[axis], d = dir[axis];
    if (d == 0) {
      if (o < lo || o > hi) return false;
      continue;
    }
    double t0 = (lo - o) / d, t1 = (hi - o) / d;
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
    if (enter > leave) return false;
  }
  return true;
}

std::size_t cone_count(double half_angle, double resolution) {
  // The small margin keeps alpha = k delta from gaining a degenerate cone of half-angle ~1e-17.
  return half_angle > 0 ? static_cast<std::size_t>(std::ceil(half_angle / resolution - 1e-9)) : 0;
}

// The mount's pose in the world: a body's, or the world frame itself for none.
void mount_pose(dBodyID body, Eigen::Vector3d& position, Eigen::Matrix3d& rotation) {
  if (!body) {
    position.setZero();
    rotation.setIdentity();
    return;
  }
  const dReal* p = dBodyGetPosition(body);
  const dReal* r = dBodyGetRotation(body);  // 3x4, row-major
  position << p[0], p[1], p[2];
  rotation << r[0], r[1], r[2], r[4], r[5], r[6], r[8], r[9], r[10];
}

}  // namespace

void RangeSensor::RayDeleter::operator()(dGeomID ray) const { dGeomDestroy(ray); }

int RangeSensor::rays_on_cone(double theta_rad, double resolution_rad) {
  // Neighbours 2 pi / n apart around a cone of half-angle theta are 2 asin(sin theta sin(pi / n))
  // apart in angle; setting that to delta and solving for n gives the count.
  const double ratio = std::sin(0.5 * resolution_rad) / std::sin(theta_rad);
  if (!(ratio < 1)) return 3;
  // The margin keeps a count that is a whole number but for rounding from gaining a ray.
  const double n = std::ceil(kPi / std::asin(ratio) - 1e-9);
  return std::max(3, static_cast<int>(n));
}

RangeSensor::RangeSensor(const RangeBeam& beam) : beam_(beam) {
  if (!(beam.half_angle_rad >= 0 && beam.half_angle_rad < 0.5 * kPi))
    throw std::invalid_argument("range beam: half-angle must be in [0, 90) degrees");
  if (!(beam.resolution_rad > 0)) throw std::invalid_argument("range beam: resolution must be > 0");
  if (!(beam.max_range_m > 0)) throw std::invalid_argument("range beam: max range must be > 0 m");
  if (!(beam.min_range_m >= 0 && beam.min_range_m <= beam.max_range_m))
    throw std::invalid_argument("range beam: min range must be in [0, max range]");

  const std::size_t cones = cone_count(beam.half_angle_rad, beam.resolution_rad);
  std::size_t total = 1;
  for (std::size_t k = 0; k < cones && total <= kMaxRays; ++k)
    total += static_cast<std::size_t>(
        rays_on_cone(beam.half_angle_rad - static_cast<double>(k) * beam.resolution_rad, beam.resolution_rad));
  if (total > kMaxRays)
    throw std::invalid_argument("range beam: half-angle and resolution call for more than " +
                                std::to_string(kMaxRays) + " rays");

  // The pattern is built about +x, then turned by the mount's yaw and (downward-positive) pitch.
  const Eigen::Matrix3d mount = (Eigen::AngleAxisd(beam.yaw_rad, Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(beam.pitch_rad, Eigen::Vector3d::UnitY()))
                                    .toRotationMatrix();
  directions_.reserve(total);
  directions_.push_back(mount * Eigen::Vector3d::UnitX());
  for (std::size_t k = 0; k < cones; ++k) {
    const double theta = beam.half_angle_rad - static_cast<double>(k) * beam.resolution_rad;
    const int n = rays_on_cone(theta, beam.resolution_rad);
    for (int j = 0; j < n; ++j) {
      const double phi = 2 * kPi * j / n;
      const Eigen::Vector3d d(std::cos(theta), std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi));
      directions_.push_back((mount * d).normalized());
    }
  }
  world_directions_.resize(directions_.size());
}

void RangeSensor::gather(dSpaceID space, const double bounds[6], int ignore_entity, std::vector<Candidate>& out) {
  const int count = dSpaceGetNumGeoms(space);
  for (int i = 0; i < count; ++i) {  // sequential indices are O(1) each in ODE's spaces
    dGeomID geom = dSpaceGetGeom(space, i);
    if (dGeomIsSpace(geom)) {
      gather(reinterpret_cast<dSpaceID>(geom), bounds, ignore_entity, out);
      continue;
    }
    // Untagged geoms take part in no contact (PhysicsWorld::collide_pair): not solid to a ray either.
    const auto* tag = static_cast<const GeomTag*>(dGeomGetData(geom));
    if (!tag || (ignore_entity >= 0 && tag->entity == ignore_entity)) continue;
    if (tag->role == GeomRole::Tread) continue;  // meets only the ground; rays see the tyre
    Candidate c{geom, tag->entity, {}};
    dGeomGetAABB(geom, c.aabb);  // brings a moved body's box up to date first
    bool overlaps = true;
    for (int axis = 0; axis < 3 && overlaps; ++axis)
      overlaps = c.aabb[2 * axis] <= bounds[2 * axis + 1] + kAabbSlack_m &&
                 c.aabb[2 * axis + 1] >= bounds[2 * axis] - kAabbSlack_m;
    if (overlaps) out.push_back(c);
  }
}

Eigen::Vector3d RangeSensor::place(const Eigen::Vector3d& mount_position_m, const Eigen::Matrix3d& mount_rotation,
                                   double bounds[6]) const {
  const Eigen::Vector3d origin = mount_position_m + mount_rotation * beam_.position_m;
  for (int axis = 0; axis < 3; ++axis) {
    bounds[2 * axis] = std::min(bounds[2 * axis], origin[axis]);
    bounds[2 * axis + 1] = std::max(bounds[2 * axis + 1], origin[axis]);
  }
  for (std::size_t i = 0; i < directions_.size(); ++i) {
    world_directions_[i] = mount_rotation * directions_[i];
    const Eigen::Vector3d end = origin + beam_.max_range_m * world_directions_[i];
    for (int axis = 0; axis < 3; ++axis) {
      bounds[2 * axis] = std::min(bounds[2 * axis], end[axis]);
      bounds[2 * axis + 1] = std::max(bounds[2 * axis + 1], end[axis]);
    }
  }
  return origin;
}

RangeReading RangeSensor::cast(const Eigen::Vector3d& origin, const std::vector<Candidate>& candidates,
                               bool first_hit_will_do) const {
  if (!ray_) {
    ray_.reset(dCreateRay(nullptr, beam_.max_range_m));
    // Every triangle a ray crosses is considered and the nearest kept; both faces count.
    dGeomRaySetFirstContact(ray_.get(), 0);
    dGeomRaySetBackfaceCull(ray_.get(), 0);
    dGeomRaySetClosestHit(ray_.get(), 1);
  }
  RangeReading reading;
  reading.distance_m = beam_.max_range_m;
  // Only a hit closer than the best so far can change the answer: each hit shortens every later ray.
  double limit = beam_.max_range_m;
  dContactGeom contacts[kMaxContacts];
  for (const Eigen::Vector3d& dir : world_directions_) {
    bool ray_placed = false;
    for (const Candidate& c : candidates) {
      if (!segment_meets_box(origin, dir, limit, c.aabb)) continue;
      if (!ray_placed) {
        dGeomRaySet(ray_.get(), origin.x(), origin.y(), origin.z(), dir.x(), dir.y(), dir.z());
        ray_placed = true;
      }
      dGeomRaySetLength(ray_.get(), limit);
      const int n = dCollide(ray_.get(), c.geom, kMaxContacts, contacts, sizeof(dContactGeom));
      for (int k = 0; k < n; ++k) {
        // Distance from the contact point rather than ODE's depth: a heightfield's contact for a
        // ray wholly below it carries a penetration depth, not a distance along the ray.
        const Eigen::Vector3d point(contacts[k].pos[0], contacts[k].pos[1], contacts[k].pos[2]);
        const double t = (point - origin).dot(dir);
        if (!(t >= 0 && t <= limit)) continue;
        if (reading.hit && t >= reading.distance_m) continue;
        reading.hit = true;
        reading.distance_m = t;
        reading.point_m = point;
        reading.entity = c.entity;
        limit = t;
        if (first_hit_will_do) return reading;
      }
    }
  }
  reading.below_min = reading.hit && reading.distance_m < beam_.min_range_m;
  return reading;
}

RangeReading RangeSensor::measure(const PhysicsWorld& physics, dBodyID mount_body, int ignore_entity) const {
  Eigen::Vector3d position;
  Eigen::Matrix3d rotation;
  mount_pose(mount_body, position, rotation);
  return measure(physics, position, rotation, ignore_entity);
}

RangeReading RangeSensor::measure(const PhysicsWorld& physics, const Eigen::Vector3d& mount_position_m,
                                  const Eigen::Matrix3d& mount_rotation, int ignore_entity) const {
  // One pass over the spaces per call, keeping only geoms whose boxes meet the beam's, instead of
  // one per ray: ODE's spaces test a ray against every geom they hold.
  double bounds[6] = {kInf, -kInf, kInf, -kInf, kInf, -kInf};
  const Eigen::Vector3d origin = place(mount_position_m, mount_rotation, bounds);
  candidates_.clear();
  gather(physics.static_space(), bounds, ignore_entity, candidates_);
  gather(physics.dynamic_space(), bounds, ignore_entity, candidates_);
  return cast(origin, candidates_, false);
}

RangeSensorSet::RangeSensorSet(std::vector<RangeSensor> sensors) : sensors_(std::move(sensors)) {
  origins_.resize(sensors_.size());
}

RangeSensorSet::RangeSensorSet(const std::vector<RangeBeam>& beams) {
  sensors_.reserve(beams.size());
  for (const RangeBeam& beam : beams) sensors_.emplace_back(beam);
  origins_.resize(sensors_.size());
}

bool RangeSensorSet::any_hit(const PhysicsWorld& physics, dBodyID mount_body, int ignore_entity) const {
  Eigen::Vector3d position;
  Eigen::Matrix3d rotation;
  mount_pose(mount_body, position, rotation);
  return any_hit(physics, position, rotation, ignore_entity);
}

bool RangeSensorSet::any_hit(const PhysicsWorld& physics, const Eigen::Vector3d& mount_position_m,
                             const Eigen::Matrix3d& mount_rotation, int ignore_entity) const {
  double bounds[6] = {kInf, -kInf, kInf, -kInf, kInf, -kInf};
  for (std::size_t i = 0; i < sensors_.size(); ++i) origins_[i] = sensors_[i].place(mount_position_m, mount_rotation, bounds);
  candidates_.clear();
  RangeSensor::gather(physics.static_space(), bounds, ignore_entity, candidates_);
  RangeSensor::gather(physics.dynamic_space(), bounds, ignore_entity, candidates_);
  // Short rays wholly above the highest terrain sample under them cannot reach the ground: most
  // steps of a bump lever on open ground are then spared ten ray-heightfield tests.
  if (bounds[4] > physics.terrain_ceiling(bounds)) {
    dGeomID terrain = physics.terrain_geom();
    candidates_.erase(std::remove_if(candidates_.begin(), candidates_.end(),
                                     [terrain](const RangeSensor::Candidate& c) { return c.geom == terrain; }),
                      candidates_.end());
  }
  // A geom near one beam but not another is skipped per ray by the box test in cast(): the
  // shared list finds the same hits as each sensor's own.
  for (std::size_t i = 0; i < sensors_.size(); ++i)
    if (sensors_[i].cast(origins_[i], candidates_, true).hit) return true;
  return false;
}

}  // namespace sear
