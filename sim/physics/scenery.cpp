#include "physics/scenery.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace sear {
namespace {

void set_yaw(dGeomID geom, double yaw) {
  dMatrix3 r;
  dRFromAxisAndAngle(r, 0, 0, 1, yaw);
  dGeomSetRotation(geom, r);
}

// Lowest terrain point under a footprint, so that walls and trunks reach the ground everywhere;
// NaN where some point has no terrain under it.
double lowest_ground(const PhysicsWorld& physics, const std::vector<Eigen::Vector2d>& points) {
  double lowest = 1e300;
  for (const auto& p : points) {
    const double h = physics.terrain_height(p.x(), p.y(), std::nan(""));
    if (std::isnan(h)) return h;
    lowest = std::min(lowest, h);
  }
  return lowest;
}

}  // namespace

void build_terrain(PhysicsWorld& physics, const TerrainDesc& terrain) {
  const int material = physics.material_index(terrain.material);
  dGeomID geom = nullptr;
  switch (terrain.kind) {
    case TerrainKind::Flat:
      geom = dCreatePlane(physics.static_space(), 0, 0, 1, 0);
      break;
    case TerrainKind::Heightmap: {
      dHeightfieldDataID data = physics.add_heightfield_data();
      const auto [lo, hi] = std::minmax_element(terrain.heights_m.begin(), terrain.heights_m.end());
      // ODE samples index (x + z * columns) from the -x, -z corner. Its heightfields are Y-up; we
      // turn the geom +90 degrees about X so local Y is world up, which sends local +Z to world
      // south: local row 0 is then the north edge, exactly the image's top row.
      dGeomHeightfieldDataBuildDouble(data, terrain.heights_m.data(), 1, terrain.size_m.x(), terrain.size_m.y(),
                                      terrain.columns, terrain.rows, 1.0, 0.0, 1.0, 0);
      dGeomHeightfieldDataSetBounds(data, *lo, *hi);
      geom = dCreateHeightfield(physics.static_space(), data, 1);
      dMatrix3 r;
      dRFromAxisAndAngle(r, 1, 0, 0, M_PI / 2);
      dGeomSetRotation(geom, r);
      break;
    }
    case TerrainKind::Mesh:
      geom = dCreateTriMesh(physics.static_space(), physics.add_mesh_data(terrain.mesh), nullptr, nullptr, nullptr);
      break;
  }
  physics.tag(geom, GeomRole::Terrain, -1, material);
  physics.set_terrain_geom(geom);
}

std::vector<std::string> build_obstacles(PhysicsWorld& physics, const WorldDesc& world, const std::string& file) {
  std::vector<std::string> problems;
  const auto off_terrain = [&](double ground, int line, const std::string& name) {
    if (!std::isnan(ground)) return false;
    problems.push_back(fmt::format("{}:{}: error: obstacle '{}' has no terrain under it", file, line, name));
    return true;
  };
  for (const auto& box : world.boxes) {
    double z = box.z_m;
    if (box.on_ground) {
      const double ground = lowest_ground(physics, {box.xy_m});
      if (off_terrain(ground, box.line, box.name)) continue;
      z = ground + 0.5 * box.size_m.z();
    }
    const int entity = physics.add_entity(box.name);
    const bool dynamic = box.mass_kg > 0;
    dGeomID geom = dCreateBox(dynamic ? physics.dynamic_space() : physics.static_space(), box.size_m.x(),
                              box.size_m.y(), box.size_m.z());
    if (dynamic) {
      dBodyID body = dBodyCreate(physics.world());
      dMass mass;
      dMassSetBoxTotal(&mass, box.mass_kg, box.size_m.x(), box.size_m.y(), box.size_m.z());
      dBodySetMass(body, &mass);
      dGeomSetBody(geom, body);
    }
    dGeomSetPosition(geom, box.xy_m.x(), box.xy_m.y(), z);
    set_yaw(geom, box.yaw_rad);
    physics.tag(geom, GeomRole::Obstacle, entity, physics.material_index(box.material));
  }

  for (const auto& tree : world.trees) {
    const double r = tree.trunk_radius_m;
    const Eigen::Vector2d c = tree.xy_m;
    const double ground = lowest_ground(physics, {c, c + Eigen::Vector2d(r, 0), c - Eigen::Vector2d(r, 0),
                                                  c + Eigen::Vector2d(0, r), c - Eigen::Vector2d(0, r)});
    if (off_terrain(ground, tree.line, tree.name)) continue;
    const int entity = physics.add_entity(tree.name);
    const int material = physics.material_index(tree.material);
    dGeomID trunk = dCreateCylinder(physics.static_space(), r, tree.trunk_height_m);  // ODE cylinders run along Z
    dGeomSetPosition(trunk, c.x(), c.y(), ground + 0.5 * tree.trunk_height_m);
    physics.tag(trunk, GeomRole::Obstacle, entity, material);
    if (tree.crown_radius_m > 0) {
      dGeomID crown = dCreateSphere(physics.static_space(), tree.crown_radius_m);
      dGeomSetPosition(crown, c.x(), c.y(), ground + tree.trunk_height_m);
      physics.tag(crown, GeomRole::Obstacle, entity, material);
    }
  }

  for (const auto& wall : world.walls) {
    const Eigen::Vector2d along = wall.to_m - wall.from_m;
    const Eigen::Vector2d mid = 0.5 * (wall.from_m + wall.to_m);
    const double ground = lowest_ground(physics, {wall.from_m, mid, wall.to_m});
    if (off_terrain(ground, wall.line, wall.name)) continue;
    const int entity = physics.add_entity(wall.name);
    dGeomID geom = dCreateBox(physics.static_space(), along.norm(), wall.thickness_m, wall.height_m);
    dGeomSetPosition(geom, mid.x(), mid.y(), ground + 0.5 * wall.height_m);
    set_yaw(geom, std::atan2(along.y(), along.x()));
    physics.tag(geom, GeomRole::Obstacle, entity, physics.material_index(wall.material));
  }

  for (const auto& mesh : world.meshes) {
    const double ground = lowest_ground(physics, {mesh.xy_m});
    if (off_terrain(ground, mesh.line, mesh.name)) continue;
    const int entity = physics.add_entity(mesh.name);
    dGeomID geom =
        dCreateTriMesh(physics.static_space(), physics.add_mesh_data(mesh.mesh), nullptr, nullptr, nullptr);
    dGeomSetPosition(geom, mesh.xy_m.x(), mesh.xy_m.y(), ground);
    set_yaw(geom, mesh.yaw_rad);
    physics.tag(geom, GeomRole::Obstacle, entity, physics.material_index(mesh.material));
  }
  return problems;
}

}  // namespace sear
