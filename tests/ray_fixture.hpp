// Worlds to cast rays in and ODE's own answer to check them against, shared by the range sensor and
// ray scene tests. The reference is written independently of the code under test on purpose.
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "physics/physics_world.hpp"
#include "physics/scenery.hpp"
#include "runtime/simulation.hpp"
#include "scene/project_loader.hpp"
#include "sensors/ray_scene.hpp"
#include "test_world.hpp"

namespace sear::test {

// A world's terrain and obstacles, with no robot. The description outlives the physics world: a
// heightfield reads its heights from it.
struct Scene {
  explicit Scene(const std::string& world_children)
      : project(project_from_xml(project_xml(R"(step="0.001")", world_children, ""))), physics(project.world, 1) {
    build_terrain(physics, project.world.terrain);
    const auto problems = build_obstacles(physics, project.world, project.file);
    if (!problems.empty()) throw std::runtime_error(problems.front());
  }
  ProjectDesc project;
  PhysicsWorld physics;
};

inline int entity_of(const PhysicsWorld& physics, const std::string& name) {
  const auto& names = physics.entity_names();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  throw std::invalid_argument("no entity '" + name + "'");
}

// The default project's world and rover (no firmware), settled for `settle_s`: terrain, walls,
// boxes, trees, a mesh rock, a loose parcel and a robot, to check every kind of geom at once.
struct DefaultWorld {
  explicit DefaultWorld(double settle_s) : project(load()), sim(project, 1) { run_for(sim, settle_s); }
  static ProjectDesc load() {
    Diagnostics diagnostics;
    auto p = load_project(std::string(SEAR_ASSET_DIR) + "/projects/default.xml", diagnostics);
    if (!p) throw std::runtime_error(diagnostics.joined());
    for (auto& robot : p->robots) robot.mcus.clear();
    return *p;
  }
  ProjectDesc project;
  Simulation sim;
};

// One full-length ODE ray against each tagged geom of `geoms` (but `ignore_entity`'s), from either
// side, with no box culling and no shortening: the closest contact kept.
inline RayHit ode_closest_hit(const std::vector<dGeomID>& geoms, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& dir, double length, int ignore_entity) {
  dGeomID ray = dCreateRay(nullptr, length);
  dGeomRaySetFirstContact(ray, 0);
  dGeomRaySetBackfaceCull(ray, 0);
  dGeomRaySetClosestHit(ray, 1);
  dGeomRaySet(ray, origin.x(), origin.y(), origin.z(), dir.x(), dir.y(), dir.z());
  RayHit best;
  for (dGeomID g : geoms) {
    const auto* tag = static_cast<const GeomTag*>(dGeomGetData(g));
    if (!tag || (ignore_entity >= 0 && tag->entity == ignore_entity)) continue;
    dContactGeom contacts[64];
    const int n = dCollide(ray, g, 64, contacts, sizeof(dContactGeom));
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d point(contacts[k].pos[0], contacts[k].pos[1], contacts[k].pos[2]);
      const double t = (point - origin).dot(dir);
      if (t < 0 || t > length || (best.hit && t >= best.distance_m)) continue;
      best.hit = true;
      best.distance_m = t;
      best.point_m = point;
      best.normal_m = Eigen::Vector3d(contacts[k].normal[0], contacts[k].normal[1], contacts[k].normal[2]);
      best.entity = tag->entity;
    }
  }
  dGeomDestroy(ray);
  return best;
}

}  // namespace sear::test
