// The live ODE world: bodies, two collision spaces (static scenery, and everything that moves),
// contact rules per material, and the record of which robot touched what in the last step.
#pragma once

#include <ode/ode.h>

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "scene/description.hpp"

namespace sear {

// What a geom is: decides its contact friction and whether touching it counts as a collision.
enum class GeomRole : std::uint8_t { Terrain, Obstacle, Chassis, Wheel, Caster };

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
  void tag(dGeomID geom, GeomRole role, int entity, int material);

  // Keeps triangle data alive as long as the geoms built from it.
  dTriMeshDataID add_mesh_data(const TriangleMesh& mesh);
  dHeightfieldDataID add_heightfield_data();

  // Height of the terrain under (x, y), or `fallback` where there is none (off the heightmap).
  double terrain_height(double x, double y, double fallback = 0.0) const;
  void set_terrain_geom(dGeomID geom) { terrain_geom_ = geom; }

  void step();
  const std::vector<Touch>& touches() const { return touches_; }  // during the last step

 private:
  static void near_callback(void* self, dGeomID a, dGeomID b);
  void collide_pair(dGeomID a, dGeomID b);

  std::vector<Material> materials_;
  double step_s_;
  dWorldID world_;
  dSpaceID static_space_;
  dSpaceID dynamic_space_;
  dJointGroupID contacts_;
  dGeomID terrain_geom_ = nullptr;
  std::deque<GeomTag> tags_;  // stable addresses: geoms point at their tag
  std::vector<std::string> entity_names_;
  std::vector<dTriMeshDataID> mesh_data_;
  std::vector<dHeightfieldDataID> heightfield_data_;
  std::deque<TriangleMesh> meshes_;
  std::vector<Touch> touches_;
};

}  // namespace sear
