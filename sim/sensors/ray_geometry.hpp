// Ray tests both ray paths need to answer alike: the static scene's refinement (sensors/ray_scene)
// and the moving bodies' ODE rays (sensors/range_sensor) cull and keep hits the same way, so that
// a reading does not depend on which of them found it.
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>
#include <algorithm>
#include <utility>

#include "sensors/ray_scene.hpp"

namespace sear::detail {

// Room for rounding in ODE's boxes and in the slab test, so that no true hit is culled.
constexpr double kAabbSlack_m = 1e-6;

// Whether two boxes (ODE's order) meet, or come within `margin` of it on every axis; false for a
// NaN bound. The cheap test that leaves most geoms out of a beam's or a ray's way.
inline bool boxes_meet(const double a[6], const double b[6], double margin) {
  for (int axis = 0; axis < 3; ++axis)
    if (!(a[2 * axis] <= b[2 * axis + 1] + margin && a[2 * axis + 1] >= b[2 * axis] - margin)) return false;
  return true;
}

// Whether the segment origin + t dir, t in [0, length], meets the box (ODE's order); the cheap test
// that spares the exact collider most rays. Infinite bounds (a plane's) work: no 0 * inf arises.
inline bool segment_meets_box(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double length,
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

// Makes `out` the hit at t along the unit `dir`, its normal turned to face the ray's origin:
// colliders report a surface's normal from whichever side they built it.
inline void record_hit(RayHit& out, double t, const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                       const Eigen::Vector3d& dir, int entity) {
  out.hit = true;
  out.distance_m = t;
  out.point_m = point;
  out.normal_m = normal.dot(dir) > 0 ? Eigen::Vector3d(-normal) : normal;
  out.entity = entity;
}

// The nearest of n ray contacts from dCollide with t in [0, limit], nearer than a hit `out` already
// holds, recorded there as `entity`'s; true if one was. With `first_hit_will_do`, the first such.
// The distance comes from the contact point rather than ODE's depth: a heightfield's contact for a
// ray wholly below it carries a penetration depth, not a distance along the ray.
inline bool take_nearest_contact(const dContactGeom* contacts, int n, const Eigen::Vector3d& origin,
                                 const Eigen::Vector3d& dir, double limit, int entity, bool first_hit_will_do,
                                 RayHit& out) {
  bool found = false;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d point(contacts[k].pos[0], contacts[k].pos[1], contacts[k].pos[2]);
    const double t = (point - origin).dot(dir);
    if (!(t >= 0 && t <= limit) || (out.hit && t >= out.distance_m)) continue;
    record_hit(out, t, point, Eigen::Vector3d(contacts[k].normal[0], contacts[k].normal[1], contacts[k].normal[2]),
               dir, entity);
    found = true;
    if (first_hit_will_do) break;
  }
  return found;
}

}  // namespace sear::detail
