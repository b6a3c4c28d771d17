#include "sensors/range_sensor.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "sensors/ray_geometry.hpp"

namespace sear {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

// A heightfield reports every terrain cell plane a ray crosses, unsorted; room for a ray skimming
// many hills. Other geoms report at most one contact per ray.
constexpr int kMaxContacts = 32;

using detail::kAabbSlack_m;
using detail::segment_meets_box;

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

// A ray in no space that reports the nearest of every contact, from either face.
dGeomID new_ray() {
  dGeomID ray = dCreateRay(nullptr, 1.0);
  dGeomRaySetFirstContact(ray, 0);
  dGeomRaySetBackfaceCull(ray, 0);
  dGeomRaySetClosestHit(ray, 1);
  return ray;
}

// The nearest hit of one ray among `candidates` with t <= limit (and < out.distance_m if out
// already holds a hit); true if it found one. With `first_hit_will_do`, the first it finds.
bool ode_ray(dGeomID ray, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
             const std::vector<detail::RayCandidate>& candidates, double limit, bool first_hit_will_do, RayHit& out) {
  bool ray_placed = false, found = false;
  dContactGeom contacts[kMaxContacts];
  for (const detail::RayCandidate& c : candidates) {
    if (!segment_meets_box(origin, dir, limit, c.aabb)) continue;
    if (!ray_placed) {
      dGeomRaySet(ray, origin.x(), origin.y(), origin.z(), dir.x(), dir.y(), dir.z());
      ray_placed = true;
    }
    // Only a hit closer than the best so far can change the answer: each hit shortens the ray.
    dGeomRaySetLength(ray, limit);
    const int n = dCollide(ray, c.geom, kMaxContacts, contacts, sizeof(dContactGeom));
    if (!detail::take_nearest_contact(contacts, n, origin, dir, limit, c.entity, first_hit_will_do, out)) continue;
    found = true;
    limit = out.distance_m;
    if (first_hit_will_do) return true;
  }
  return found;
}

void gather_geoms(const std::vector<dGeomID>& geoms, const double bounds[6], int ignore_entity,
                  std::vector<detail::RayCandidate>& out) {
  for (dGeomID geom : geoms) {
    const auto* tag = static_cast<const GeomTag*>(dGeomGetData(geom));
    if (!tag || (ignore_entity >= 0 && tag->entity == ignore_entity)) continue;
    detail::RayCandidate c{geom, tag->entity, {}};
    dGeomGetAABB(geom, c.aabb);
    if (detail::boxes_meet(c.aabb, bounds, kAabbSlack_m)) out.push_back(c);
  }
}

void take(RangeReading& reading, const RayHit& hit) {
  reading.hit = true;
  reading.distance_m = hit.distance_m;
  reading.point_m = hit.point_m;
  reading.normal_m = hit.normal_m;
  reading.entity = hit.entity;
}

RayHit as_hit(const RangeReading& r) {
  RayHit h;
  h.hit = r.hit;
  h.distance_m = r.distance_m;
  h.point_m = r.point_m;
  h.normal_m = r.normal_m;
  h.entity = r.entity;
  return h;
}

// The exact static hit of ray `dir` that Embree found at `bvh`, within limit: refined, or where
// refining fails on an edge and Embree's hit is clearly inside the limit, ODE's own answer.
RayHit exact_static(const RayScene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, const BvhHit& bvh,
                    double limit, double slack, int ignore_entity) {
  RayHit h;
  if (!std::isfinite(bvh.t)) return h;
  if (scene.refine(origin, dir, limit, bvh, ignore_entity, h)) return h;
  if (bvh.t < limit - slack) return scene.ode_nearest(origin, dir, limit, ignore_entity);
  return h;
}

}  // namespace

void detail::RayDeleter::operator()(dGeomID ray) const { dGeomDestroy(ray); }

namespace {

// rays_on_cone() in doubles: an absurd resolution asks for more rays than an int holds.
double rays_on_cone_count(double theta_rad, double resolution_rad) {
  // Neighbours 2 pi / n apart around a cone of half-angle theta are 2 asin(sin theta sin(pi / n))
  // apart in angle; setting that to delta and solving for n gives the count.
  const double ratio = std::sin(0.5 * resolution_rad) / std::sin(theta_rad);
  if (!(ratio < 1)) return 3;
  // The margin keeps a count that is a whole number but for rounding from gaining a ray.
  return std::max(3.0, std::ceil(kPi / std::asin(ratio) - 1e-9));
}

}  // namespace

int RangeSensor::rays_on_cone(double theta_rad, double resolution_rad) {
  return static_cast<int>(rays_on_cone_count(theta_rad, resolution_rad));
}

double RangeSensor::ray_count(double half_angle_rad, double resolution_rad) {
  double total = 1;
  if (!(half_angle_rad > 0)) return total;
  // Counted in doubles and given up past a million, ten times what a beam may have, so that a
  // refusal can say how many a beam asked for, and a resolution of 1e-300 is refused, not counted.
  const double cones = std::ceil(half_angle_rad / resolution_rad - 1e-9);
  for (double k = 0; k < cones && total <= 1e6; ++k)
    total += rays_on_cone_count(half_angle_rad - k * resolution_rad, resolution_rad);
  return total;
}

RangeSensor::RangeSensor(const RangeBeam& beam) : beam_(beam) {
  if (!(beam.half_angle_rad >= 0 && beam.half_angle_rad < 0.5 * kPi))
    throw std::invalid_argument("range beam: half-angle must be in [0, 90) degrees");
  if (!(beam.resolution_rad > 0)) throw std::invalid_argument("range beam: resolution must be > 0");
  if (!(beam.max_range_m > 0)) throw std::invalid_argument("range beam: max range must be > 0 m");
  if (!(beam.min_range_m >= 0 && beam.min_range_m <= beam.max_range_m))
    throw std::invalid_argument("range beam: min range must be in [0, max range]");
  if (!(beam.max_incidence_rad > 0 && beam.max_incidence_rad <= 0.5 * kPi + 1e-12))
    throw std::invalid_argument("range beam: max incidence must be in (0, 90] degrees");

  const double total = ray_count(beam.half_angle_rad, beam.resolution_rad);
  if (total > static_cast<double>(kMaxRays))
    throw std::invalid_argument("range beam: half-angle and resolution call for more than " +
                                std::to_string(kMaxRays) + " rays");
  const std::size_t cones = cone_count(beam.half_angle_rad, beam.resolution_rad);

  // The pattern is built about +x, then turned by the mount's yaw and (downward-positive) pitch.
  const Eigen::Matrix3d mount = (Eigen::AngleAxisd(beam.yaw_rad, Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(beam.pitch_rad, Eigen::Vector3d::UnitY()))
                                    .toRotationMatrix();
  directions_.reserve(static_cast<std::size_t>(total));
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
  bvh_hits_.resize(directions_.size());
}

dGeomID RangeSensor::ray() const {
  // Created on first use, when a PhysicsWorld exists and so ODE is initialised.
  if (!ray_) ray_.reset(new_ray());
  return ray_.get();
}

namespace {

// A geom a ray may strike, if its box meets the beam's.
void consider(dGeomID geom, const double aabb[6], const double bounds[6], int ignore_entity,
              std::vector<detail::RayCandidate>& out) {
  // Untagged geoms take part in no contact (PhysicsWorld::collide_pair): not solid to a ray either.
  const auto* tag = static_cast<const GeomTag*>(dGeomGetData(geom));
  if (!tag || (ignore_entity >= 0 && tag->entity == ignore_entity)) return;
  if (tag->role == GeomRole::Tread) return;  // meets only the ground; rays see the tyre
  if (!detail::boxes_meet(aabb, bounds, kAabbSlack_m)) return;
  out.push_back({geom, tag->entity, {aabb[0], aabb[1], aabb[2], aabb[3], aabb[4], aabb[5]}});
}

}  // namespace

void RangeSensor::gather(dSpaceID space, const double bounds[6], int ignore_entity, std::vector<Candidate>& out) {
  for_each_geom(space, [&](dGeomID geom) {
    double aabb[6];
    dGeomGetAABB(geom, aabb);  // brings a moved body's box up to date first
    consider(geom, aabb, bounds, ignore_entity, out);
  });
}

void RangeSensor::gather_moving(const PhysicsWorld& physics, const double bounds[6], int ignore_entity,
                                std::vector<Candidate>& out) {
  const std::vector<PhysicsWorld::GeomBox>* listed = physics.moving_held_still();
  if (!listed) {
    gather(physics.dynamic_space(), bounds, ignore_entity, out);
    return;
  }
  for (const PhysicsWorld::GeomBox& g : *listed) consider(g.geom, g.aabb, bounds, ignore_entity, out);
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
                               bool first_hit_will_do, RangeReading reading) const {
  if (candidates.empty()) return reading;
  RayHit best = as_hit(reading);
  for (const Eigen::Vector3d& dir : world_directions_) {
    const double limit = best.hit ? best.distance_m : beam_.max_range_m;
    if (ode_ray(ray(), origin, dir, candidates, limit, first_hit_will_do, best) && first_hit_will_do) break;
  }
  if (best.hit) take(reading, best);
  return reading;
}

RangeReading RangeSensor::nearest_static(const RayScene& scene, const Eigen::Vector3d& origin,
                                         int ignore_entity) const {
  RangeReading reading;
  reading.distance_m = beam_.max_range_m;
  const std::size_t n = world_directions_.size();
  const double slack = RayScene::float_slack_m(beam_.max_range_m, origin.norm());
  scene.cast(&origin, true, world_directions_.data(), n, beam_.max_range_m + slack, ignore_entity, bvh_hits_.data());
  // Rays in order of Embree's distance, each refined, until no float distance left can come within
  // rounding of the best exact one: usually one or two rays of a bundle are ever refined.
  for (;;) {
    std::size_t next = n;
    float t = std::numeric_limits<float>::infinity();
    for (std::size_t i = 0; i < n; ++i)
      if (bvh_hits_[i].t < t) {
        t = bvh_hits_[i].t;
        next = i;
      }
    if (next == n || (reading.hit && t > reading.distance_m + slack)) break;
    const BvhHit bvh = bvh_hits_[next];
    bvh_hits_[next].t = std::numeric_limits<float>::infinity();
    const double limit = reading.hit ? reading.distance_m : beam_.max_range_m;
    const RayHit h = exact_static(scene, origin, world_directions_[next], bvh, limit, slack, ignore_entity);
    if (h.hit && (!reading.hit || h.distance_m < reading.distance_m)) take(reading, h);
  }
  return reading;
}

RangeReading RangeSensor::nearest_echo(const RayScene& scene, const Eigen::Vector3d& origin, const double bounds[6],
                                       const std::vector<Candidate>& candidates, int ignore_entity) const {
  RangeReading reading;
  reading.distance_m = beam_.max_range_m;
  const std::size_t n = world_directions_.size();
  const double slack = RayScene::float_slack_m(beam_.max_range_m, origin.norm());
  const double reach = beam_.max_range_m + slack;
  // Each ray's own nearest surface decides whether that ray echoes: a grazing wall in front of a
  // square-on one hides it from that ray.
  const double min_cos = std::cos(beam_.max_incidence_rad);
  // A ray that can strike nothing static but the terrain, and lies too flat to it for any of its
  // cells to echo, is no echo wherever it strikes: it is not cast at all (as if it struck nothing,
  // which keeps the other rays' order below). A sonar cone's rays over open ground are nearly all
  // such: their casts and each hit met again in double were four fifths of the cone's cost.
  // Nothing moving may be near, as it could stand in front of the ground.
  const double grazing_cos = candidates.empty() ? scene.grazing_cos(beam_.max_incidence_rad) : -1;
  cast_rays_.clear();
  if (grazing_cos > 0) {
    scene.others_near(bounds, slack, ignore_entity, near_boxes_);
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d& dir = world_directions_[i];
      bool may_echo = !(std::abs(scene.terrain_up().dot(dir)) < grazing_cos);
      for (std::size_t b = 0; !may_echo && b < near_boxes_.size(); ++b)
        may_echo = segment_meets_box(origin, dir, reach, near_boxes_[b].data());
      if (may_echo) cast_rays_.push_back(static_cast<std::uint32_t>(i));
    }
  }
  if (grazing_cos > 0 && cast_rays_.size() < n) {
    cast_dirs_.clear();
    for (const std::uint32_t i : cast_rays_) cast_dirs_.push_back(world_directions_[i]);
    cast_hits_.resize(cast_rays_.size());
    if (!cast_dirs_.empty())
      scene.cast(&origin, true, cast_dirs_.data(), cast_dirs_.size(), reach, ignore_entity, cast_hits_.data());
    for (BvhHit& h : bvh_hits_) h.t = std::numeric_limits<float>::infinity();
    for (std::size_t k = 0; k < cast_rays_.size(); ++k) bvh_hits_[cast_rays_[k]] = cast_hits_[k];
  } else {
    scene.cast(&origin, true, world_directions_.data(), n, reach, ignore_entity, bvh_hits_.data());
  }
  // Rays in the order of their static surfaces' float distances (stable: ties keep the beam's
  // order). Once an echo is nearer than the next ray's surface can be, no later ray can beat it,
  // and asking each of them of ODE (which a sonar cone's ~200 rays cost every 10 ms) is spared;
  // a moving body could still lie in front of those surfaces, so with any nearby every ray is asked.
  // With none, a ray that meets no static surface (or was not cast) has nothing to strike and is
  // left out: over open ground that is most of a sonar cone, and sorting it cost as much as a cast.
  ray_order_.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (!candidates.empty() || std::isfinite(bvh_hits_[i].t)) ray_order_.push_back(static_cast<std::uint32_t>(i));
  std::stable_sort(ray_order_.begin(), ray_order_.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return bvh_hits_[a].t < bvh_hits_[b].t; });
  for (const std::uint32_t i : ray_order_) {
    if (candidates.empty() && reading.hit && !(static_cast<double>(bvh_hits_[i].t) - slack <= reading.distance_m)) break;
    const Eigen::Vector3d& dir = world_directions_[i];
    RayHit h = exact_static(scene, origin, dir, bvh_hits_[i], beam_.max_range_m, slack, ignore_entity);
    ode_ray(ray(), origin, dir, candidates, h.hit ? h.distance_m : beam_.max_range_m, false, h);
    if (!h.hit || std::abs(h.normal_m.dot(dir)) < min_cos) continue;  // no hit, or no echo
    if (!reading.hit || h.distance_m < reading.distance_m) take(reading, h);
  }
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
  double bounds[6] = {kInf, -kInf, kInf, -kInf, kInf, -kInf};
  const Eigen::Vector3d origin = place(mount_position_m, mount_rotation, bounds);
  const RayScene& scene = RayScene::of(physics);
  // Bodies that move, and any static geom the BVH does not hold, through ODE: one pass over the
  // dynamic space per call, keeping only geoms whose boxes meet the beam's.
  candidates_.clear();
  gather_moving(physics, bounds, ignore_entity, candidates_);
  gather_geoms(scene.ode_only(), bounds, ignore_entity, candidates_);
  RangeReading reading;
  if (beam_.max_incidence_rad < 0.5 * kPi) {
    reading = nearest_echo(scene, origin, bounds, candidates_, ignore_entity);
  } else {
    reading = cast(origin, candidates_, false, nearest_static(scene, origin, ignore_entity));
  }
  reading.below_min = reading.hit && reading.distance_m < beam_.min_range_m;
  return reading;
}

RangeReading RangeSensor::measure_ode_only(const PhysicsWorld& physics, const Eigen::Vector3d& mount_position_m,
                                           const Eigen::Matrix3d& mount_rotation, int ignore_entity) const {
  double bounds[6] = {kInf, -kInf, kInf, -kInf, kInf, -kInf};
  const Eigen::Vector3d origin = place(mount_position_m, mount_rotation, bounds);
  candidates_.clear();
  gather(physics.static_space(), bounds, ignore_entity, candidates_);
  gather(physics.dynamic_space(), bounds, ignore_entity, candidates_);
  RangeReading reading;
  reading.distance_m = beam_.max_range_m;
  const double min_cos = std::cos(beam_.max_incidence_rad);
  for (const Eigen::Vector3d& dir : world_directions_) {
    RayHit h;
    if (!ode_ray(ray(), origin, dir, candidates_, beam_.max_range_m, false, h)) continue;
    if (beam_.max_incidence_rad < 0.5 * kPi && std::abs(h.normal_m.dot(dir)) < min_cos) continue;
    if (!reading.hit || h.distance_m < reading.distance_m) take(reading, h);
  }
  reading.below_min = reading.hit && reading.distance_m < beam_.min_range_m;
  return reading;
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
  const RayScene& scene = RayScene::of(physics);
  double bounds[6] = {kInf, -kInf, kInf, -kInf, kInf, -kInf};
  ray_origins_.clear();
  ray_directions_.clear();
  std::vector<double>& reach = reach_;
  reach.clear();
  double longest = 0, farthest_origin = 0;
  for (std::size_t i = 0; i < sensors_.size(); ++i) {
    const RangeSensor& s = sensors_[i];
    origins_[i] = s.place(mount_position_m, mount_rotation, bounds);
    // A sensor with specular loss echoes or not ray by ray: it answers for itself below.
    if (s.beam_.max_incidence_rad < 0.5 * kPi) continue;
    for (const Eigen::Vector3d& d : s.world_directions_) {
      ray_origins_.push_back(origins_[i]);
      ray_directions_.push_back(d);
      reach.push_back(s.beam_.max_range_m);
    }
    longest = std::max(longest, s.beam_.max_range_m);
    farthest_origin = std::max(farthest_origin, origins_[i].norm());
  }
  // The static world first, all the lever's rays in one packet: most presses are against it, and
  // it spares the pass over every robot's parts. A lever clear of every static geom's box and above
  // the terrain under it, as a driving robot's mostly is, is not cast at all: the packet was half
  // of a bump switch's cost, every quantum.
  const double slack = RayScene::float_slack_m(longest, farthest_origin);
  if (!ray_directions_.empty() && !scene.clear_of(bounds, physics.terrain_ceiling(bounds), slack, ignore_entity)) {
    bvh_hits_.resize(ray_directions_.size());
    scene.cast(ray_origins_.data(), false, ray_directions_.data(), ray_directions_.size(), longest + slack,
               ignore_entity, bvh_hits_.data());
    for (std::size_t k = 0; k < bvh_hits_.size(); ++k) {
      if (!(bvh_hits_[k].t <= reach[k] + slack)) continue;
      if (exact_static(scene, ray_origins_[k], ray_directions_[k], bvh_hits_[k], reach[k], slack, ignore_entity).hit)
        return true;
    }
  }
  for (const RangeSensor& s : sensors_)
    if (s.beam_.max_incidence_rad < 0.5 * kPi && s.measure(physics, mount_position_m, mount_rotation, ignore_entity).hit)
      return true;
  candidates_.clear();
  RangeSensor::gather_moving(physics, bounds, ignore_entity, candidates_);
  gather_geoms(scene.ode_only(), bounds, ignore_entity, candidates_);
  // A geom near one beam but not another is skipped per ray by the box test in cast(): the
  // shared list finds the same hits as each sensor's own.
  for (std::size_t i = 0; i < sensors_.size(); ++i) {
    if (sensors_[i].beam_.max_incidence_rad < 0.5 * kPi) continue;
    RangeReading none;
    none.distance_m = sensors_[i].beam_.max_range_m;
    if (sensors_[i].cast(origins_[i], candidates_, true, none).hit) return true;
  }
  return false;
}

RangeScan::RangeScan(const ScanFan& fan) : fan_(fan) {
  if (!(fan.count >= 1 && fan.count <= static_cast<int>(RangeSensor::kMaxRays)))
    throw std::invalid_argument("range scan: count must be in [1, " + std::to_string(RangeSensor::kMaxRays) + "]");
  if (!(fan.max_range_m > 0)) throw std::invalid_argument("range scan: max range must be > 0 m");
  if (!std::isfinite(fan.first_angle_rad) || !std::isfinite(fan.step_rad) || !fan.position_m.allFinite())
    throw std::invalid_argument("range scan: angles and position must be finite");
  cos_.resize(static_cast<std::size_t>(fan.count));
  sin_.resize(static_cast<std::size_t>(fan.count));
  for (int i = 0; i < fan.count; ++i) {
    const double a = fan.first_angle_rad + i * fan.step_rad;
    cos_[static_cast<std::size_t>(i)] = static_cast<float>(std::cos(a));
    sin_[static_cast<std::size_t>(i)] = static_cast<float>(std::sin(a));
  }
}

Eigen::Vector3d RangeScan::direction(int i) const {
  const double a = fan_.first_angle_rad + i * fan_.step_rad;
  return {std::sin(a), -std::cos(a), 0.0};
}

void RangeScan::scan(const PhysicsWorld& physics, dBodyID mount_body, int ignore_entity, float* distances_m) const {
  Eigen::Vector3d position;
  Eigen::Matrix3d rotation;
  mount_pose(mount_body, position, rotation);
  scan(physics, position, rotation, ignore_entity, distances_m);
}

namespace {

// The box of a fan's rays from `origin` along cos a + sin b out to `range`.
void fan_bounds(const Eigen::Vector3d& origin, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                const std::vector<float>& cos_table, const std::vector<float>& sin_table, double range, double bounds[6]) {
  for (int axis = 0; axis < 3; ++axis) bounds[2 * axis] = bounds[2 * axis + 1] = origin[axis];
  for (std::size_t i = 0; i < cos_table.size(); ++i) {
    const Eigen::Vector3d end = origin + range * (cos_table[i] * a + sin_table[i] * b);
    for (int axis = 0; axis < 3; ++axis) {
      bounds[2 * axis] = std::min(bounds[2 * axis], end[axis]);
      bounds[2 * axis + 1] = std::max(bounds[2 * axis + 1], end[axis]);
    }
  }
}

}  // namespace

namespace {

// The angles (about the fan's axis, from a towards b) a box's corners span seen from `origin`,
// widened a little; false when the box lies wholly to one side of the fan's plane. Where the
// origin is inside the box, or the box wraps round it by half a turn, every angle.
bool box_angles(const Eigen::Vector3d& origin, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                const Eigen::Vector3d& normal, const double aabb[6], double& lo, double& hi) {
  double below = kInf, above = -kInf;
  Eigen::Vector3d v[8];
  for (int k = 0; k < 8; ++k) {
    v[k] = Eigen::Vector3d(aabb[k & 1 ? 1 : 0], aabb[k & 2 ? 3 : 2], aabb[k & 4 ? 5 : 4]) - origin;
    const double side = v[k].dot(normal);
    below = std::min(below, side);
    above = std::max(above, side);
  }
  if (below > kAabbSlack_m || above < -kAabbSlack_m) return false;
  lo = -kPi;
  hi = kPi;
  const Eigen::Vector3d centre = 0.5 * (v[0] + v[7]);
  const double mid = std::atan2(centre.dot(b), centre.dot(a));
  double from = 0, to = 0;
  for (const auto& corner : v) {
    const double x = corner.dot(a), y = corner.dot(b);
    if (std::hypot(x, y) < kAabbSlack_m) return true;
    // Within half a turn of the centre's angle: from the atan2 of the corner in a frame turned to it.
    const double d = std::atan2(y * std::cos(mid) - x * std::sin(mid), x * std::cos(mid) + y * std::sin(mid));
    from = std::min(from, d);
    to = std::max(to, d);
  }
  if (to - from >= 0.9 * kPi) return true;  // the origin is (nearly) inside: every angle
  // Float directions and double angles part by about 1e-7 rad; 1e-6 keeps every ray that meets it.
  lo = mid + from - 1e-6;
  hi = mid + to + 1e-6;
  return true;
}

// Calls f(i) for each ray i in [0, count) whose angle first + i step lies in [lo, hi] modulo 2 pi.
template <typename F>
void rays_within(double first, double step, int count, double lo, double hi, F&& f) {
  if (hi - lo >= 2 * kPi - 1e-9) {
    for (int i = 0; i < count; ++i) f(static_cast<std::size_t>(i));
    return;
  }
  const double last = first + (count - 1) * step;
  const double span_lo = std::min(first, last), span_hi = std::max(first, last);
  if (step == 0) {
    const double turns = std::ceil((lo - first) / (2 * kPi));
    if (first + 2 * kPi * turns <= hi)
      for (int i = 0; i < count; ++i) f(static_cast<std::size_t>(i));
    return;
  }
  // The window lo..hi shifted by whole turns to every place the fan's angles reach.
  const long m0 = static_cast<long>(std::floor((span_lo - hi) / (2 * kPi)));
  const long m1 = static_cast<long>(std::ceil((span_hi - lo) / (2 * kPi)));
  for (long m = m0; m <= m1; ++m) {
    const double w0 = lo + 2 * kPi * static_cast<double>(m), w1 = hi + 2 * kPi * static_cast<double>(m);
    double i0 = (w0 - first) / step, i1 = (w1 - first) / step;
    if (i0 > i1) std::swap(i0, i1);
    const double begin = std::max(0.0, std::ceil(i0)), end = std::min(static_cast<double>(count - 1), std::floor(i1));
    for (double i = begin; i <= end; ++i) f(static_cast<std::size_t>(i));
  }
}

}  // namespace

void RangeScan::scan(const PhysicsWorld& physics, const Eigen::Vector3d& mount_position_m,
                     const Eigen::Matrix3d& mount_rotation, int ignore_entity, float* distances_m) const {
  const RayScene& scene = RayScene::of(physics);
  const Eigen::Vector3d origin = mount_position_m + mount_rotation * fan_.position_m;
  const Eigen::Vector3d a = -mount_rotation.col(1), b = mount_rotation.col(0);
  const std::size_t n = cos_.size();
  scene.cast_fan(origin, a, b, cos_.data(), sin_.data(), n, fan_.max_range_m, ignore_entity, distances_m);

  double bounds[6];
  fan_bounds(origin, a, b, cos_, sin_, fan_.max_range_m, bounds);
  candidates_.clear();
  RangeSensor::gather_moving(physics, bounds, ignore_entity, candidates_);
  gather_geoms(scene.ode_only(), bounds, ignore_entity, candidates_);
  if (candidates_.empty()) return;
  if (!ray_) ray_.reset(new_ray());
  const Eigen::Vector3d normal = a.cross(b);
  for (const auto& c : candidates_) {
    // Only the rays whose direction lies within the angles the box spans in the fan's plane can
    // meet it, and none if the box lies wholly off that plane: a body beside the robot costs the
    // few rays that point at it, not a box test for each of the 361.
    double lo = 0, hi = 0;
    if (!box_angles(origin, a, b, normal, c.aabb, lo, hi)) continue;
    const std::vector<detail::RayCandidate> one{c};
    rays_within(fan_.first_angle_rad, fan_.step_rad, fan_.count, lo, hi, [&](std::size_t i) {
      const double limit = std::isfinite(distances_m[i]) ? distances_m[i] : fan_.max_range_m;
      const Eigen::Vector3d dir = (cos_[i] * a + sin_[i] * b).normalized();
      if (!segment_meets_box(origin, dir, limit, c.aabb)) return;
      RayHit h;
      if (ode_ray(ray_.get(), origin, dir, one, limit, false, h)) distances_m[i] = static_cast<float>(h.distance_m);
    });
  }
}

void RangeScan::scan_ode_only(const PhysicsWorld& physics, const Eigen::Vector3d& mount_position_m,
                              const Eigen::Matrix3d& mount_rotation, int ignore_entity, float* distances_m) const {
  const Eigen::Vector3d origin = mount_position_m + mount_rotation * fan_.position_m;
  const Eigen::Vector3d a = -mount_rotation.col(1), b = mount_rotation.col(0);
  double bounds[6];
  fan_bounds(origin, a, b, cos_, sin_, fan_.max_range_m, bounds);
  candidates_.clear();
  RangeSensor::gather(physics.static_space(), bounds, ignore_entity, candidates_);
  RangeSensor::gather(physics.dynamic_space(), bounds, ignore_entity, candidates_);
  if (!ray_) ray_.reset(new_ray());
  for (std::size_t i = 0; i < cos_.size(); ++i) {
    const Eigen::Vector3d dir = (cos_[i] * a + sin_[i] * b).normalized();
    RayHit h;
    ode_ray(ray_.get(), origin, dir, candidates_, fan_.max_range_m, false, h);
    distances_m[i] = h.hit ? static_cast<float>(h.distance_m) : std::numeric_limits<float>::infinity();
  }
}

}  // namespace sear
