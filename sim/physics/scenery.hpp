// Builds the terrain (flat, heightmap, mesh) and the obstacles (boxes, trees, walls, meshes) of a
// world description into a PhysicsWorld.
#pragma once

#include "physics/physics_world.hpp"

namespace sear {

void build_terrain(PhysicsWorld& physics, const TerrainDesc& terrain);
void build_obstacles(PhysicsWorld& physics, const WorldDesc& world);

}  // namespace sear
