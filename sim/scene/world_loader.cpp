// Reads <world>: gravity, step, GPS origin, magnetic north, materials, terrain and obstacles.
#include <fmt/format.h>
#include <tinyxml2.h>

#include <cmath>
#include <filesystem>

#include "scene/heightmap_image.hpp"
#include "scene/loader_parts.hpp"
#include "scene/nearest_name.hpp"
#include "scene/value_ranges.hpp"

#include <unordered_map>
#include <unordered_set>

namespace sear {
namespace {

void read_terrain(ElementReader& r, TerrainDesc& t) {
  const std::size_t kind = r.choice("type", {"flat", "heightmap", "mesh"}, 0);
  t.material = r.text("material", "default");
  if (kind == 0) {
    t.kind = TerrainKind::Flat;
  } else if (kind == 1) {
    t.kind = TerrainKind::Heightmap;
    const auto rel = r.required_text("image");
    t.size_m = r.vec2("size", {0, 0}, ranges::kTerrainSide);
    const double lo = r.number("min_height", 0.0, ranges::kHeight, "m");
    const double hi = r.number("max_height", 1.0, ranges::kHeight, "m");
    if (!r.has("size")) r.error("<terrain type=\"heightmap\"> needs attribute 'size' (\"x y\" in metres)");
    if (hi < lo) r.error("<terrain> 'max_height' must not be below 'min_height'");
    if (rel) {
      const std::string path = path_beside(r.file(), *rel);
      if (!check_readable_file(r, "image", *rel, path)) {
      } else if (const HeightmapImage image = load_heightmap_image(path); !image.error.empty()) {
        r.error(fmt::format("<terrain> image '{}': {}", *rel, image.error));
      } else {
        t.columns = image.columns;
        t.rows = image.rows;
        t.heights_m.reserve(image.levels.size());
        for (double level : image.levels) t.heights_m.push_back(lo + level * (hi - lo));
      }
    }
  } else {
    t.kind = TerrainKind::Mesh;
    t.mesh = read_mesh_file(r);
  }
  r.finish();
}

}  // namespace

void read_world(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics,
                WorldDesc& world) {
  ElementReader r(&element, file, diagnostics);
  check_at_most_one(element, file, diagnostics, {"terrain", "gps_origin", "magnetic"});
  world.gravity = r.vec3("gravity", world.gravity, ranges::kGravity);
  world.step_s = r.number("step", world.step_s, ranges::kStep, "s");
  world.solver = r.choice("solver", {"direct", "iterative"}, 0) == 1 ? WorldDesc::Solver::Iterative
                                                                      : WorldDesc::Solver::Direct;
  world.solver_iterations =
      static_cast<int>(r.whole_number("solver_iterations", world.solver_iterations, ranges::kSolverIterations));
  world.materials.push_back(Material{"default", 0.8, 0.0});
  struct MaterialUse {
    std::string material;
    int line;
    std::string what;
  };
  std::vector<MaterialUse> uses;  // checked once all materials are known, so their order does not matter
  // Where each material is in world.materials: a world with many materials stays linear to read.
  std::unordered_map<std::string, std::size_t> material_at{{"default", 0}};
  r.children({"gps_origin", "magnetic", "material", "terrain", "box", "tree", "wall", "mesh"},
             [&](const tinyxml2::XMLElement& child) {
               ElementReader c(&child, file, diagnostics);
               const std::string kind = child.Name();
               if (kind == "gps_origin") {
                 world.gps_origin.latitude_deg =
                     c.required_number("latitude", ranges::kLatitude, "deg").value_or(0);
                 world.gps_origin.longitude_deg = c.required_number("longitude", ranges::kLongitude, "deg").value_or(0);
                 world.gps_origin.altitude_m = c.number("altitude", 0.0, ranges::kAltitude, "m");
               } else if (kind == "magnetic") {
                 world.magnetic_declination_rad =
                     c.number("declination_deg", NAN, ranges::kDeclination, "deg") * kDegToRad;
                 world.magnetic_inclination_rad =
                     c.number("inclination_deg", NAN, ranges::kInclination, "deg") * kDegToRad;
                 world.magnetic_intensity_T = c.number("intensity_nt", NAN, ranges::kFieldIntensity, "nT") * 1e-9;
                 world.magnetic_year = c.number("year", world.magnetic_year, ranges::kMagneticYear);
               } else if (kind == "material") {
                 const Material m = read_material_element(c);
                 if (m.name.empty()) return;
                 const auto [at, fresh] = material_at.emplace(m.name, world.materials.size());
                 if (fresh) world.materials.push_back(m);
                 else if (m.name == "default") world.materials[at->second] = m;  // the user may redefine the default
                 else c.error(fmt::format("material '{}' is defined twice", m.name));
                 return;
               } else if (kind == "terrain") {
                 read_terrain(c, world.terrain);
                 uses.push_back({world.terrain.material, c.line(), "terrain"});
                 return;
               } else if (kind == "box") {
                 BoxDesc b;
                 b.name = c.text("name", fmt::format("box{}", world.boxes.size() + 1));
                 check_name(c, b.name);
                 b.line = c.line();
                 b.size_m = c.vec3("size", b.size_m, ranges::kObstacleSize);
                 b.xy_m = c.vec2("pos", b.xy_m, ranges::kWorldXY);
                 b.on_ground = !c.has("z");
                 b.z_m = c.number("z", 0.0, ranges::kHeight, "m");
                 b.yaw_rad = c.number("yaw_deg", 0.0, ranges::kYaw, "deg") * kDegToRad;
                 b.mass_kg = c.number("mass", 0.0, ranges::kObstacleMass, "kg");
                 b.material = c.text("material", "default");
                 uses.push_back({b.material, c.line(), "box '" + b.name + "'"});
                 world.boxes.push_back(b);
               } else if (kind == "tree") {
                 TreeDesc t;
                 t.name = c.text("name", fmt::format("tree{}", world.trees.size() + 1));
                 check_name(c, t.name);
                 t.line = c.line();
                 t.xy_m = c.vec2("pos", t.xy_m, ranges::kWorldXY);
                 t.trunk_radius_m = c.number("trunk_radius", t.trunk_radius_m, ranges::kObstacleSize, "m");
                 t.trunk_height_m = c.number("trunk_height", t.trunk_height_m, ranges::kTrunkHeight, "m");
                 t.crown_radius_m = c.number("crown_radius", t.crown_radius_m, ranges::kCrownRadius, "m");
                 t.material = c.text("material", "default");
                 uses.push_back({t.material, c.line(), "tree '" + t.name + "'"});
                 world.trees.push_back(t);
               } else if (kind == "wall") {
                 WallDesc w;
                 w.name = c.text("name", fmt::format("wall{}", world.walls.size() + 1));
                 check_name(c, w.name);
                 w.line = c.line();
                 w.from_m = c.vec2("from", w.from_m, ranges::kWorldXY);
                 w.to_m = c.vec2("to", w.to_m, ranges::kWorldXY);
                 w.height_m = c.number("height", w.height_m, ranges::kObstacleSize, "m");
                 w.thickness_m = c.number("thickness", w.thickness_m, ranges::kObstacleSize, "m");
                 w.material = c.text("material", "default");
                 if ((w.to_m - w.from_m).norm() < 1e-6) c.error("<wall> 'from' and 'to' are the same point");
                 uses.push_back({w.material, c.line(), "wall '" + w.name + "'"});
                 world.walls.push_back(w);
               } else if (kind == "mesh") {
                 MeshObstacleDesc m;
                 m.name = c.text("name", fmt::format("mesh{}", world.meshes.size() + 1));
                 check_name(c, m.name);
                 m.line = c.line();
                 m.xy_m = c.vec2("pos", m.xy_m, ranges::kWorldXY);
                 m.yaw_rad = c.number("yaw_deg", 0.0, ranges::kYaw, "deg") * kDegToRad;
                 m.material = c.text("material", "default");
                 m.mesh = read_mesh_file(c);
                 uses.push_back({m.material, c.line(), "mesh '" + m.name + "'"});
                 world.meshes.push_back(std::move(m));
               }
               c.finish();
             });
  r.finish();

  std::vector<std::string> names;
  for (const auto& m : world.materials) names.push_back(m.name);
  for (const auto& use : uses) {
    if (!material_at.count(use.material))
      diagnostics.error(file, use.line,
                        fmt::format("{} uses unknown material '{}'{}", use.what, use.material,
                                    did_you_mean(diagnostics, use.material, names)));
  }
}

}  // namespace sear
