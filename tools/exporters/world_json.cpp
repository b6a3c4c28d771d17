#include "exporters/world_json.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "scene/device_kind.hpp"

namespace sear {
namespace {

using Json = nlohmann::ordered_json;

Json xy(double x, double y) { return Json::array({x, y}); }

// Every `stride`-th sample of the heightmap, so that a plot never carries more than the grid cap.
Json heightmap_grid(const TerrainDesc& t) {
  const int stride = std::max(1, (std::max(t.columns, t.rows) + kWorldJsonMaxGrid - 1) / kWorldJsonMaxGrid);
  Json rows = Json::array();
  for (int r = 0; r < t.rows; r += stride) {
    Json row = Json::array();
    for (int c = 0; c < t.columns; c += stride)
      row.push_back(t.heights_m[static_cast<std::size_t>(r) * static_cast<std::size_t>(t.columns) +
                                static_cast<std::size_t>(c)]);
    rows.push_back(std::move(row));
  }
  return rows;
}

// A mesh terrain as a grid like a heightmap's: the highest vertex in each cell, null where no
// vertex falls (large flat triangles), row 0 north.
Json mesh_terrain(const TerrainDesc& t, Json& terrain) {
  const auto& v = t.mesh.vertices;
  if (v.empty()) return Json::array();
  float x0 = v[0].x(), x1 = x0, y0 = v[0].y(), y1 = y0;
  for (const auto& p : v) {
    x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x());
    y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
  }
  const int n = 128;
  std::vector<double> top(n * n, -std::numeric_limits<double>::infinity());
  const auto cell = [n](float a, float lo, float hi) {
    return hi > lo ? std::clamp(static_cast<int>((a - lo) / (hi - lo) * n), 0, n - 1) : 0;
  };
  for (const auto& p : v) {
    const int c = cell(p.x(), x0, x1), r = n - 1 - cell(p.y(), y0, y1);
    top[r * n + c] = std::max(top[r * n + c], static_cast<double>(p.z()));
  }
  terrain["center_m"] = xy((x0 + x1) / 2.0, (y0 + y1) / 2.0);
  terrain["size_m"] = xy(x1 - x0, y1 - y0);
  Json rows = Json::array();
  for (int r = 0; r < n; ++r) {
    Json row = Json::array();
    for (int c = 0; c < n; ++c) row.push_back(std::isfinite(top[r * n + c]) ? Json(top[r * n + c]) : Json());
    rows.push_back(std::move(row));
  }
  return rows;
}

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

// A mesh obstacle's outline seen from above: the convex hull of its vertices where it stands
// (Andrew's monotone chain), counter-clockwise.
Json footprint(const MeshObstacleDesc& m) {
  const double c = std::cos(m.yaw_rad), s = std::sin(m.yaw_rad);
  std::vector<Eigen::Vector2d> p;
  for (const auto& v : m.mesh.vertices)
    p.emplace_back(m.xy_m.x() + c * v.x() - s * v.y(), m.xy_m.y() + s * v.x() + c * v.y());
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) {
    Json out = Json::array();
    for (const auto& q : p) out.push_back(xy(q.x(), q.y()));
    return out;
  }
  std::vector<Eigen::Vector2d> hull(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  Json out = Json::array();
  for (std::size_t i = 0; i + 1 < k; ++i) out.push_back(xy(hull[i].x(), hull[i].y()));
  return out;
}

const char* terrain_kind(TerrainKind k) {
  switch (k) {
    case TerrainKind::Flat: return "flat";
    case TerrainKind::Heightmap: return "heightmap";
    case TerrainKind::Mesh: return "mesh";
  }
  return "?";
}

Json devices_of(const McuDesc& mcu) {
  Json out = Json::array();
  for (const DeviceDesc& d : mcu.devices) {
    Json wires = Json::object();
    if (d.kind)
      for (std::size_t i = 0; i < d.kind->wires.size() && i < d.wires.size(); ++i)
        if (d.wires[i] >= 0) wires[d.kind->wires[i].attribute] = d.wires[i];
    // Parameters in SI units (degrees as radians), a name's text as text: a GPS's utc_start
    // turns the times in its sentences back into sim time.
    Json params = Json::object();
    if (d.kind)
      for (std::size_t i = 0; i < d.kind->params.size() && i < d.values.size(); ++i) {
        const bool text = i < d.texts.size() && !d.texts[i].empty();
        params[d.kind->params[i].attribute] = text ? Json(d.texts[i]) : Json(d.values[i]);
      }
    out.push_back({{"name", d.name},
                   {"element", d.kind ? d.kind->element : ""},
                   {"wires", std::move(wires)},
                   {"params", std::move(params)}});
  }
  return out;
}

}  // namespace

std::string world_json(const ProjectDesc& project) {
  const WorldDesc& w = project.world;
  Json j;
  j["project"] = project.name;
  j["gps_origin"] = {{"latitude_deg", w.gps_origin.latitude_deg},
                     {"longitude_deg", w.gps_origin.longitude_deg},
                     {"altitude_m", w.gps_origin.altitude_m}};
  Json terrain = {{"kind", terrain_kind(w.terrain.kind)}};
  if (w.terrain.kind == TerrainKind::Heightmap) {
    terrain["center_m"] = xy(0, 0);
    terrain["size_m"] = xy(w.terrain.size_m.x(), w.terrain.size_m.y());
    terrain["heights_m"] = heightmap_grid(w.terrain);
  } else if (w.terrain.kind == TerrainKind::Mesh) {
    terrain["heights_m"] = mesh_terrain(w.terrain, terrain);
  }
  j["terrain"] = std::move(terrain);

  Json boxes = Json::array(), trees = Json::array(), walls = Json::array(), meshes = Json::array();
  for (const BoxDesc& b : w.boxes)
    boxes.push_back({{"name", b.name},
                     {"center_m", xy(b.xy_m.x(), b.xy_m.y())},
                     {"size_m", {b.size_m.x(), b.size_m.y(), b.size_m.z()}},
                     {"yaw_rad", b.yaw_rad},
                     {"movable", b.mass_kg > 0}});
  for (const TreeDesc& t : w.trees)
    trees.push_back({{"name", t.name},
                     {"center_m", xy(t.xy_m.x(), t.xy_m.y())},
                     {"trunk_radius_m", t.trunk_radius_m},
                     {"crown_radius_m", t.crown_radius_m}});
  for (const WallDesc& wall : w.walls)
    walls.push_back({{"name", wall.name},
                     {"from_m", xy(wall.from_m.x(), wall.from_m.y())},
                     {"to_m", xy(wall.to_m.x(), wall.to_m.y())},
                     {"thickness_m", wall.thickness_m},
                     {"height_m", wall.height_m}});
  for (const MeshObstacleDesc& m : w.meshes)
    meshes.push_back({{"name", m.name}, {"center_m", xy(m.xy_m.x(), m.xy_m.y())}, {"footprint_m", footprint(m)}});
  j["obstacles"] = {{"boxes", boxes}, {"trees", trees}, {"walls", walls}, {"meshes", meshes}};

  Json robots = Json::array();
  for (const RobotDesc& r : project.robots) {
    Json mcus = Json::array();
    for (const McuDesc& m : r.mcus)
      mcus.push_back({{"name", m.name}, {"avcc_v", m.avcc_v}, {"aref_v", m.aref_v}, {"devices", devices_of(m)}});
    robots.push_back({{"name", r.name},
                      {"start_m", xy(r.start_xy_m.x(), r.start_xy_m.y())},
                      {"start_yaw_rad", r.start_yaw_rad},
                      {"length_m", r.chassis.size_m.x()},
                      {"width_m", r.chassis.size_m.y()},
                      {"mcus", std::move(mcus)}});
  }
  j["robots"] = std::move(robots);
  return j.dump() + "\n";  // compact: a 256 x 256 grid indented would be megabytes
}

void write_world_json(const std::string& path, const ProjectDesc& project) {
  std::ofstream out(path, std::ios::binary);
  out << world_json(project);
  if (!out) throw std::runtime_error(path + ": error: cannot write");
}

}  // namespace sear
