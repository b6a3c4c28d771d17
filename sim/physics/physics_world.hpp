// The live ODE world: bodies, two collision spaces (static scenery, and everything that moves),
// contact rules per material, and the record of which robot touched what in the last step.
#pragma once

#include <ode/ode.h>

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "physics/broadphase.hpp"
#include "physics/constraint_solver.hpp"
#include "scene/description.hpp"

namespace sear {

class RayScene;  // sensors/ray_scene.hpp

// What a geom is: decides its contact friction and whether touching it counts as a collision.
// A wheel has two geoms: its tyre (Wheel), a cylinder that meets obstacles, other robots and
// rays, and its tread (Tread), a sphere of the same radius that meets only the terrain. Rolling
// on the terrain then makes one smooth contact point instead of a cylinder's several, which took
// 11-17 % off each step of the default world; the tread's sideways bulge never reaches anything
// but the ground.
enum class GeomRole : std::uint8_t { Terrain, Obstacle, Chassis, Wheel, Caster, Tread };

struct GeomTag {
  GeomRole role;
  int entity;    // index into PhysicsWorld::entity_names(): an obstacle or a robot
  int material;  // index into the world's materials
};

// A robot part in contact with an obstacle or another robot during one step.
struct Touch {
  int robot_entity;
  int other_entity;
  bool operator==(const Touch& o) const { return robot_entity == o.robot_entity && other_entity == o.other_entity; }
};

// Calls f(geom) for each geom of `space` and of the spaces within it, in ODE's list order (a
// sub-space's geoms where it stands); sequential indices are O(1) each in ODE's spaces.
template <class F>
void for_each_geom(dSpaceID space, F&& f) {
  const int count = dSpaceGetNumGeoms(space);
  for (int i = 0; i < count; ++i) {
    dGeomID geom = dSpaceGetGeom(space, i);
    if (dGeomIsSpace(geom)) for_each_geom(reinterpret_cast<dSpaceID>(geom), f);
    else f(geom);
  }
}

class PhysicsWorld {
 public:
  PhysicsWorld(const WorldDesc& desc, std::uint64_t seed);
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  dWorldID world() const { return world_; }
  // Scenery that never moves: collided only against the dynamic space, never with itself.
  dSpaceID static_space() const { return static_space_; }
  dSpaceID dynamic_space() const { return dynamic_space_; }
  double step_s() const { return step_s_; }

  int material_index(const std::string& name) const;
  int add_entity(const std::string& name);  // an obstacle or robot that collisions are reported against
  const std::vector<std::string>& entity_names() const { return entity_names_; }
  // A loose obstacle (an Obstacle geom on a body) is set to sleep once it rests, and wakes when
  // something awake touches it; robots' bodies never sleep (see physics_world.cpp).
  void tag(dGeomID geom, GeomRole role, int entity, int material);

  // Keeps triangle data alive as long as the geoms built from it.
  dTriMeshDataID add_mesh_data(const TriangleMesh& mesh);
  dHeightfieldDataID add_heightfield_data();

  // Height of the terrain under (x, y), or `fallback` where there is none (off the heightmap).
  double terrain_height(double x, double y, double fallback = 0.0) const;
  void set_terrain_geom(dGeomID geom) { terrain_geom_ = geom; }
  dGeomID terrain_geom() const { return terrain_geom_; }
  // Keeps the heightmap's samples (or notes a flat plane) for terrain_ceiling().
  void set_terrain_samples(const TerrainDesc& terrain);
  // No point of the terrain within the box {xmin, xmax, ymin, ymax, ...} lies higher than this:
  // the highest sample of the heightmap cells the box touches (the surface between samples is
  // made of flat triangles), 0 for a flat plane, +inf for a mesh. A short ray wholly above it
  // cannot hit the terrain, which spares ODE's ray-heightfield test walking the cells.
  double terrain_ceiling(const double box[6]) const;
  // The heightmap's samples as set_terrain_samples() kept them (row-major, row 0 the north edge),
  // empty for any other terrain; what the ray scene triangulates as ODE's heightfield does.
  const std::vector<double>& terrain_samples() const { return terrain_heights_m_; }
  int terrain_columns() const { return terrain_columns_; }
  int terrain_rows() const { return terrain_rows_; }
  const Eigen::Vector2d& terrain_size_m() const { return terrain_size_m_; }

  // The static space as a ray-tracing BVH, made by RayScene::of() on first use and kept here so
  // that every sensor of this world shares one; this class only holds it.
  std::shared_ptr<const RayScene>& ray_scene_slot() const { return ray_scene_; }

  // The moving geoms with their boxes, in the dynamic space's order (ODE's list, a sub-space's
  // geoms where it stands), for a pass of sensing in which nothing moves: listed once on the
  // first ask within a HoldStill, so that each sensor's search skips walking ODE's list (eight
  // robots' sensors walked their 49 geoms eight times a step); null outside one.
  struct GeomBox {
    dGeomID geom;
    double aabb[6];
  };
  const std::vector<GeomBox>* moving_held_still() const;
  class HoldStill {
   public:
    explicit HoldStill(const PhysicsWorld& world) : world_(world) { world_.holding_still_ = true; }
    ~HoldStill() { world_.holding_still_ = world_.moving_listed_ = false; }
    HoldStill(const HoldStill&) = delete;
    HoldStill& operator=(const HoldStill&) = delete;

   private:
    const PhysicsWorld& world_;
  };

  void step();
  const std::vector<Touch>& touches() const { return touches_; }  // during the last step
  // Contact points handed to the solver in the last step: with the bodies, what a step costs.
  std::size_t contact_count() const { return contact_count_; }
  // The steps each of ODE's solvers took (see ConstraintSolver).
  const ConstraintSolver::Counts& solver_counts() const { return solver_.counts(); }

 private:
  static void near_callback(void* self, dGeomID a, dGeomID b);
  void collide_pair(dGeomID a, dGeomID b);
  // In a pass after sleepers woke: whether the pair has one of them and no body awake before.
  bool only_woken_or_asleep(dBodyID a, dBodyID b) const;

  std::vector<Material> materials_;
  double step_s_;
  ConstraintSolver solver_;
  std::vector<dBodyID> waking_;  // sleepers touched in this pass
  std::vector<dBodyID> woken_;   // those woken before the pass that meets them again
  bool rewaking_ = false;
  dWorldID world_;
  dSpaceID static_space_;
  dSpaceID dynamic_space_;
  std::unique_ptr<Broadphase> broadphase_;
  dJointGroupID contacts_;
  dGeomID terrain_geom_ = nullptr;
  TerrainKind terrain_kind_ = TerrainKind::Mesh;  // until set_terrain_samples() says otherwise
  int terrain_columns_ = 0, terrain_rows_ = 0;
  Eigen::Vector2d terrain_size_m_{0, 0};
  std::vector<double> terrain_heights_m_;
  std::deque<GeomTag> tags_;  // stable addresses: geoms point at their tag
  std::vector<std::string> entity_names_;
  std::vector<dTriMeshDataID> mesh_data_;
  std::vector<dHeightfieldDataID> heightfield_data_;
  std::deque<TriangleMesh> meshes_;
  std::vector<Touch> touches_;
  std::size_t contact_count_ = 0;
  mutable std::shared_ptr<const RayScene> ray_scene_;
  mutable bool holding_still_ = false, moving_listed_ = false;
  mutable std::vector<GeomBox> moving_;
};

}  // namespace sear
