// Which geoms' boxes meet in a step: the scenery kept in a grid, what moves swept along x, and
// every pair handed on in exactly the order ODE's own space collisions give, so runs stay the same.
#pragma once

#include <ode/ode.h>

#include <cstdint>
#include <utility>
#include <vector>

#include "physics/box_grid.hpp"

namespace sear {

// ODE's hash space meets a geom from outside it (dSpaceCollide2) by testing every geom it holds,
// and its simple space every pair: a robot among 400 boxes paid 14 us a step for boxes metres
// away (the default world's 12 static geoms are walked whole, as ODE did). ODE's quadtree space
// does search, but hands pairs on in its tree's order, and the order of the contacts is the
// order of the solver's rows: every trajectory that touches two things at once would change.
class Broadphase {
 public:
  // The scenery's geoms must be where they stay before the first collide(), as for RayScene;
  // the grid is built then, and again if the static space gains or loses a geom.
  Broadphase(dSpaceID static_space, dSpaceID dynamic_space) : static_(static_space), dynamic_(dynamic_space) {}

  // The same calls, in the same order, as dSpaceCollide(dynamic) and then
  // dSpaceCollide2(dynamic, static) on ODE 0.16: `callback(data, a, b)` for each pair whose boxes
  // meet, a moving geom first against the scenery.
  void collide(void* data, dNearCallback* callback);

 private:
  // A geom as collideAABBs() looks at it, read once a step.
  struct Box {
    dGeomID geom;
    dBodyID body;
    double aabb[6];
    unsigned long category, collide;
    bool enabled;  // ODE's GEOM_ENABLED: enabled, and no side of zero size

    // The checks collideAABBs() makes before the callback, bounds holding NaN counting as meeting
    // as ODE writes the test. No geom class we make overrides dxGeom::AABBTest(), which says yes.
    bool may_touch(const Box& o) const {
      if (body == o.body && body) return false;
      if (((category & o.collide) || (o.category & collide)) == 0) return false;
      return meets(o);
    }
    bool meets(const Box& o) const {
      const double* a = aabb;
      const double* b = o.aabb;
      return !(a[0] > b[1] || a[1] < b[0] || a[2] > b[3] || a[3] < b[2] || a[4] > b[5] || a[5] < b[4]);
    }
  };
  static Box box_of(dGeomID g);
  void index_scenery();
  void moving_pairs(void* data, dNearCallback* callback);

  dSpaceID static_, dynamic_;
  int indexed_count_ = -1;
  std::vector<Box> scenery_;
  bool gridded_ = false;  // small scenery is walked whole, as ODE does, only faster
  BoxGrid grid_;
  std::vector<Box> moving_;
  std::vector<std::uint32_t> order_;
  std::vector<std::uint32_t> unordered_;  // moving boxes whose x bounds are not ordered (NaN)
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs_;
};

}  // namespace sear
