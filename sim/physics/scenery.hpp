// Builds the terrain (flat, heightmap, mesh) and the obstacles (boxes, trees, walls, meshes) of a
// world description into a PhysicsWorld.
#pragma once

#include <string>
#include <vector>

#include "physics/physics_world.hpp"

namespace sear {

void build_terrain(PhysicsWorld& physics, const TerrainDesc& terrain);

// Obstacles that rest on the ground need terrain under them; each one without is left out and
// reported as "file:line: error: ..." (`file` being the project that describes the world).
std::vector<std::string> build_obstacles(PhysicsWorld& physics, const WorldDesc& world, const std::string& file);

}  // namespace sear
