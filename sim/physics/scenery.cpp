#include "physics/scenery.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <optional>

namespace sear {
namespace {

void set_yaw(dGeomID geom, double yaw) {
  dMatrix3 r;
  dRFromAxisAndAngle(r, 0, 0, 1, yaw);
  dGeomSetRotation(geom, r);
}

// A rectangle on the ground: centre, yaw of its first side, half its two sides.
struct Footprint {
  Eigen::Vector2d centre;
  double yaw_rad;
  double half_along_m;
  double half_across_m;
};

// The terrain under a footprint: the lowest and highest samples, and how much deeper than the
// lowest (or higher than the highest) the surface may still reach between samples.
struct GroundSpan {
  double lowest_m;
  double highest_m;
  double dip_m;
};

// Samples the terrain over the whole footprint on a grid aligned with it. On a heightmap the grid
// is half a cell fine, and the surface, ODE's triangles between the samples, is Lipschitz with
// the steepest cell's gradient hypot(dh_x / cell_x, dh_y / cell_y): no point of the footprint
// lies farther than half a sample diagonal from a sample, so none is lower than the lowest
// sample by more than that gradient times that distance. A mesh's triangles are unknown to
// this grid, so there the steepest step between neighbouring samples stands in for the gradient.
// nullopt when one of `must_have` (the footprint's centre, a wall's ends) has no terrain under it.
std::optional<GroundSpan> ground_under(const PhysicsWorld& physics, const TerrainDesc& terrain, const Footprint& f,
                                       const std::vector<Eigen::Vector2d>& must_have) {
  for (const auto& p : must_have)
    if (std::isnan(physics.terrain_height(p.x(), p.y(), std::nan("")))) return std::nullopt;
  if (terrain.kind == TerrainKind::Flat) return GroundSpan{0.0, 0.0, 0.0};

  double cell_x = 0.1, cell_y = 0.1;  // a mesh: 10 cm, finer than a robot's wheel
  if (terrain.kind == TerrainKind::Heightmap) {
    cell_x = terrain.size_m.x() / (terrain.columns - 1);
    cell_y = terrain.size_m.y() / (terrain.rows - 1);
  }
  const double spacing = 0.5 * std::min(cell_x, cell_y);
  constexpr double kMaxSamplesPerSide = 4000;  // a 400 m wall on a 10 cm grid; beyond, the grid coarsens
  const auto intervals = [&](double half) {
    return static_cast<int>(std::clamp(std::ceil(2 * half / spacing), 1.0, kMaxSamplesPerSide));
  };
  const int na = intervals(f.half_along_m), nc = intervals(f.half_across_m);
  const double step_a = 2 * f.half_along_m / na, step_c = 2 * f.half_across_m / nc;
  const Eigen::Vector2d along(std::cos(f.yaw_rad), std::sin(f.yaw_rad)), across(-along.y(), along.x());

  GroundSpan span{1e300, -1e300, 0.0};
  std::vector<double> previous_row(static_cast<std::size_t>(nc + 1), std::nan(""));
  double steepest = 0;  // mesh: largest height step between neighbouring samples, per metre
  for (int i = 0; i <= na; ++i) {
    double previous = std::nan("");
    for (int j = 0; j <= nc; ++j) {
      const Eigen::Vector2d p =
          f.centre + (-f.half_along_m + i * step_a) * along + (-f.half_across_m + j * step_c) * across;
      const double h = physics.terrain_height(p.x(), p.y(), std::nan(""));
      auto& above = previous_row[static_cast<std::size_t>(j)];
      if (!std::isnan(h)) {
        span.lowest_m = std::min(span.lowest_m, h);
        span.highest_m = std::max(span.highest_m, h);
        if (!std::isnan(previous)) steepest = std::max(steepest, std::abs(h - previous) / step_c);
        if (!std::isnan(above)) steepest = std::max(steepest, std::abs(h - above) / step_a);
      }
      previous = h;
      above = h;
    }
  }
  double gradient = steepest;
  if (terrain.kind == TerrainKind::Heightmap) {
    // The steepest cell edge among the cells the footprint's bounding box touches.
    const double reach = f.half_along_m + f.half_across_m;
    const auto col = [&](double x) { return (x + 0.5 * terrain.size_m.x()) / cell_x; };
    const auto row = [&](double y) { return (0.5 * terrain.size_m.y() - y) / cell_y; };
    const int c0 = std::max(0, static_cast<int>(std::floor(col(f.centre.x() - reach))) - 1);
    const int c1 = std::min(terrain.columns - 1, static_cast<int>(std::ceil(col(f.centre.x() + reach))) + 1);
    const int r0 = std::max(0, static_cast<int>(std::floor(row(f.centre.y() + reach))) - 1);
    const int r1 = std::min(terrain.rows - 1, static_cast<int>(std::ceil(row(f.centre.y() - reach))) + 1);
    const auto h = [&](int r, int c) {
      return terrain.heights_m[static_cast<std::size_t>(r) * static_cast<std::size_t>(terrain.columns) +
                               static_cast<std::size_t>(c)];
    };
    double dx = 0, dy = 0;
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) {
        if (c < c1) dx = std::max(dx, std::abs(h(r, c + 1) - h(r, c)));
        if (r < r1) dy = std::max(dy, std::abs(h(r + 1, c) - h(r, c)));
      }
    gradient = std::hypot(dx / cell_x, dy / cell_y);
  }
  span.dip_m = gradient * 0.5 * std::hypot(step_a, step_c);
  return span;
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
  physics.set_terrain_samples(terrain);
}

std::vector<std::string> build_obstacles(PhysicsWorld& physics, const WorldDesc& world, const std::string& file) {
  std::vector<std::string> problems;
  const auto off_terrain = [&](const std::optional<GroundSpan>& ground, int line, const std::string& name) {
    if (ground) return false;
    problems.push_back(fmt::format("{}:{}: error: obstacle '{}' has no terrain under it", file, line, name));
    return true;
  };
  for (const auto& box : world.boxes) {
    const bool dynamic = box.mass_kg > 0;
    double z = box.z_m;
    double height = box.size_m.z();
    if (box.on_ground) {
      const auto ground = ground_under(physics, world.terrain,
                                       {box.xy_m, box.yaw_rad, 0.5 * box.size_m.x(), 0.5 * box.size_m.y()}, {box.xy_m});
      if (off_terrain(ground, box.line, box.name)) continue;
      if (dynamic) {
        // A loose box keeps its size and is set down on the highest point under it, to settle.
        z = ground->highest_m + 0.5 * height;
      } else {
        // A fixed box reaches from below the lowest point under it to its height above the
        // highest, so it stands at least that tall everywhere and leaves no gap under its edges.
        const double bottom = ground->lowest_m - ground->dip_m;
        height = ground->highest_m + ground->dip_m + box.size_m.z() - bottom;
        z = bottom + 0.5 * height;
      }
    }
    const int entity = physics.add_entity(box.name);
    dGeomID geom = dCreateBox(dynamic ? physics.dynamic_space() : physics.static_space(), box.size_m.x(),
                              box.size_m.y(), height);
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
    const auto ground = ground_under(physics, world.terrain, {c, 0.0, r, r}, {c});
    if (off_terrain(ground, tree.line, tree.name)) continue;
    const int entity = physics.add_entity(tree.name);
    const int material = physics.material_index(tree.material);
    // The trunk, like a wall, reaches below the lowest ground under it; its top stands
    // trunk_height above the highest.
    const double bottom = ground->lowest_m - ground->dip_m;
    const double top = ground->highest_m + ground->dip_m + tree.trunk_height_m;
    dGeomID trunk = dCreateCylinder(physics.static_space(), r, top - bottom);  // ODE cylinders run along Z
    dGeomSetPosition(trunk, c.x(), c.y(), 0.5 * (bottom + top));
    physics.tag(trunk, GeomRole::Obstacle, entity, material);
    if (tree.crown_radius_m > 0) {
      dGeomID crown = dCreateSphere(physics.static_space(), tree.crown_radius_m);
      dGeomSetPosition(crown, c.x(), c.y(), top);
      physics.tag(crown, GeomRole::Obstacle, entity, material);
    }
  }

  for (const auto& wall : world.walls) {
    const Eigen::Vector2d along = wall.to_m - wall.from_m;
    const Eigen::Vector2d mid = 0.5 * (wall.from_m + wall.to_m);
    const double yaw = std::atan2(along.y(), along.x());
    const auto ground = ground_under(physics, world.terrain, {mid, yaw, 0.5 * along.norm(), 0.5 * wall.thickness_m},
                                     {wall.from_m, mid, wall.to_m});
    if (off_terrain(ground, wall.line, wall.name)) continue;
    const int entity = physics.add_entity(wall.name);
    // From below the lowest ground along and across its whole footprint to `height` above the
    // highest: nothing passes under it in a dip, and it is never lower than described.
    const double bottom = ground->lowest_m - ground->dip_m;
    const double top = ground->highest_m + ground->dip_m + wall.height_m;
    dGeomID geom = dCreateBox(physics.static_space(), along.norm(), wall.thickness_m, top - bottom);
    dGeomSetPosition(geom, mid.x(), mid.y(), 0.5 * (bottom + top));
    set_yaw(geom, yaw);
    physics.tag(geom, GeomRole::Obstacle, entity, physics.material_index(wall.material));
  }

  for (const auto& mesh : world.meshes) {
    // Its base goes to the lowest ground under the mesh's bounding rectangle: humps may poke
    // into it, but nothing shows under it.
    Eigen::Vector2f lo(1e30f, 1e30f), hi(-1e30f, -1e30f);
    for (const auto& v : mesh.mesh.vertices) {
      lo = lo.cwiseMin(v.head<2>());
      hi = hi.cwiseMax(v.head<2>());
    }
    if (mesh.mesh.vertices.empty()) lo = hi = Eigen::Vector2f::Zero();
    const Eigen::Vector2d local_centre = 0.5 * (lo + hi).cast<double>();
    const Eigen::Vector2d centre = mesh.xy_m + Eigen::Rotation2Dd(mesh.yaw_rad) * local_centre;
    const auto ground = ground_under(physics, world.terrain,
                                     {centre, mesh.yaw_rad, 0.5 * (hi.x() - lo.x()), 0.5 * (hi.y() - lo.y())},
                                     {mesh.xy_m});
    if (off_terrain(ground, mesh.line, mesh.name)) continue;
    const int entity = physics.add_entity(mesh.name);
    dGeomID geom =
        dCreateTriMesh(physics.static_space(), physics.add_mesh_data(mesh.mesh), nullptr, nullptr, nullptr);
    dGeomSetPosition(geom, mesh.xy_m.x(), mesh.xy_m.y(), ground->lowest_m - ground->dip_m);
    set_yaw(geom, mesh.yaw_rad);
    physics.tag(geom, GeomRole::Obstacle, entity, physics.material_index(mesh.material));
  }
  return problems;
}

}  // namespace sear
