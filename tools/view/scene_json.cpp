#include "view/scene_json.hpp"

#include <ode/ode.h>

#include <Eigen/Geometry>
#include <cmath>
#include <nlohmann/json.hpp>

#include "devices/mounting.hpp"
#include "exporters/world_json.hpp"
#include "lcm/reading_meaning.hpp"
#include "physics/physics_world.hpp"
#include "physics/scenery.hpp"
#include "scene/device_kind.hpp"
#include "view/frame_round.hpp"

namespace sear {
namespace {

using Json = nlohmann::ordered_json;

using sear::quat;
using sear::vec3;
Json vec3(const Eigen::Vector3d& v) { return sear::vec3(v.x(), v.y(), v.z()); }
Json quat(const Eigen::Quaterniond& q) { return sear::quat(q.w(), q.x(), q.y(), q.z()); }

// A mesh's triangles as flat arrays, thinned to at most kSceneMaxMeshTriangles (every k-th one).
void put_mesh(const TriangleMesh& mesh, Json& out) {
  const std::size_t triangles = mesh.indices.size() / 3;
  const std::size_t stride = std::max<std::size_t>(1, (triangles + kSceneMaxMeshTriangles - 1) / kSceneMaxMeshTriangles);
  // Only the kept triangles' vertices go out, renumbered in the order first used.
  constexpr std::uint32_t kUnused = UINT32_MAX;
  std::vector<std::uint32_t> renumbered(mesh.vertices.size(), kUnused);
  std::uint32_t used = 0;
  Json vertices = Json::array(), indices = Json::array();
  for (std::size_t t = 0; t < triangles; t += stride)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t old = mesh.indices[3 * t + k];
      if (old >= mesh.vertices.size()) continue;  // the loader checks; never index past the list
      if (renumbered[old] == kUnused) {
        renumbered[old] = used++;
        const auto& v = mesh.vertices[old];
        vertices.push_back(round_mm(v.x()));
        vertices.push_back(round_mm(v.y()));
        vertices.push_back(round_mm(v.z()));
      }
      indices.push_back(renumbered[old]);
    }
  out["vertices"] = std::move(vertices);
  out["indices"] = std::move(indices);
}

// The terrain as world.json has it (the same grid the plots draw), with the protocol's names.
Json terrain_of(const ProjectDesc& project) {
  const Json world = Json::parse(world_json(project));
  Json t = world.at("terrain");
  if (t["kind"] == "flat") t["kind"] = "plane";
  if (!t.contains("size_m")) t["size_m"] = Json::array({0, 0});
  if (t.contains("heights_m") && !t["heights_m"].empty()) {
    t["grid"] = Json::array({t["heights_m"][0].size(), t["heights_m"].size()});
    for (Json& row : t["heights_m"])  // to 1 mm: a third of the full-precision text
      for (Json& h : row)
        if (h.is_number()) h = round_mm(h.get<double>());
  }
  if (project.world.terrain.kind == TerrainKind::Mesh) put_mesh(project.world.terrain.mesh, t);
  return t;
}

const MeshObstacleDesc* mesh_named(const WorldDesc& w, const std::string& name) {
  for (const auto& m : w.meshes)
    if (m.name == name) return &m;
  return nullptr;
}

void add_geoms(dSpaceID space, const PhysicsWorld& physics, const WorldDesc& world, Json& out) {
  for (int i = 0; i < dSpaceGetNumGeoms(space); ++i) {
    dGeomID g = dSpaceGetGeom(space, i);
    if (dGeomIsSpace(g)) {
      add_geoms(reinterpret_cast<dSpaceID>(g), physics, world, out);
      continue;
    }
    const auto* tag = static_cast<const GeomTag*>(dGeomGetData(g));
    if (!tag || tag->role != GeomRole::Obstacle) continue;
    const dReal* p = dGeomGetPosition(g);
    dQuaternion q;
    dGeomGetQuaternion(g, q);
    const std::string& name = physics.entity_names().at(static_cast<std::size_t>(tag->entity));
    Json o = {{"name", name}, {"shape", ""}, {"pos", vec3(p[0], p[1], p[2])}, {"quat", quat(q[0], q[1], q[2], q[3])},
              {"movable", dGeomGetBody(g) != nullptr}};
    switch (dGeomGetClass(g)) {
      case dBoxClass: {
        dVector3 l;
        dGeomBoxGetLengths(g, l);
        o["shape"] = "box";
        o["size"] = vec3(l[0], l[1], l[2]);
        break;
      }
      case dCylinderClass: {
        dReal r, len;
        dGeomCylinderGetParams(g, &r, &len);
        o["shape"] = "cylinder";
        o["radius"] = round_mm(r);
        o["length"] = round_mm(len);
        break;
      }
      case dSphereClass:
        o["shape"] = "sphere";
        o["radius"] = round_mm(dGeomSphereGetRadius(g));
        break;
      case dTriMeshClass:
        o["shape"] = "mesh";
        if (const MeshObstacleDesc* m = mesh_named(world, name)) put_mesh(m->mesh, o);
        break;
      default:
        continue;
    }
    out.push_back(std::move(o));
  }
}

// Every obstacle placed exactly as a run places it (on the terrain, walls sunk below its lowest
// point): a physics world of this project built once, its obstacle geoms read back.
Json obstacles_of(const ProjectDesc& project) {
  PhysicsWorld physics(project.world, project.run.seed);
  build_terrain(physics, project.world.terrain);
  build_obstacles(physics, project.world, project.file);
  Json out = Json::array();
  add_geoms(physics.static_space(), physics, project.world, out);
  add_geoms(physics.dynamic_space(), physics, project.world, out);
  return out;
}

// The closest a ranger reports, from each part's datasheet; the cast itself starts at 0.
double datasheet_min_range_m(const std::string& element) {
  if (element == "gp2d12") return 0.10;          // GP2D12: 10 to 80 cm
  if (element == "gp2d15") return 0.10;          // GP2D15: detects from 10 cm
  if (element == "hcsr04") return 0.02;          // HC-SR04: 2 cm to 4 m
  if (element == "maxbotix_lv_ez") return 0.1524;  // LV-EZ1: 6 inches
  return 0;
}

std::string wiring_text(const DeviceDesc& d) {
  std::string text;
  if (!d.kind) return text;
  for (std::size_t i = 0; i < d.kind->wires.size() && i < d.wires.size(); ++i) {
    if (d.wires[i] < 0) continue;
    if (!text.empty()) text += ", ";
    text += std::string(d.kind->wires[i].attribute) + " " + std::to_string(d.wires[i]);
  }
  return text;
}

Json sensor_of(const DeviceDesc& d, const std::string& mcu_id) {
  const Eigen::Quaterniond q(body_from_sensor(d));
  Json s = {{"name", d.name}, {"mcu", mcu_id}, {"element", d.kind ? d.kind->element : ""}, {"view", "none"},
            {"pos", vec3(d.position_m)}, {"quat", quat(q)}};
  switch (sensor_view(d)) {
    case SensorView::Cone:
      s["view"] = "cone";
      s["beam_deg"] = round_unit(2 * d.value("half_angle_deg") / kDegToRad);
      s["min_m"] = round_mm(datasheet_min_range_m(s["element"]));
      s["max_m"] = round_mm(d.value("max_range"));
      break;
    case SensorView::Fan:
      s["view"] = "fan";
      s["start_deg"] = kLmsStartDeg;
      s["step_deg"] = kLmsStepDeg;
      s["count"] = kLmsCount;
      s["max_m"] = 81.91;  // the longest range the scanner reports (80 m modes, in cm)
      break;
    case SensorView::Gps:
      s["view"] = "gps";
      break;
    case SensorView::None:
      break;
  }
  return s;
}

// A URDF shape (collision or visual) in its body's frame, as the page's shapeGeometry reads it.
Json shape_of(const ShapeDesc& s) {
  Json o = {{"shape", ""}, {"pos", vec3(s.position_m)}, {"quat", quat(Eigen::Quaterniond(s.rotation))}};
  switch (s.kind) {
    case ShapeDesc::Kind::Box:
      o["shape"] = "box";
      o["size"] = vec3(s.size_m);
      break;
    case ShapeDesc::Kind::Cylinder:
      o["shape"] = "cylinder";
      o["radius"] = round_mm(s.size_m.x());
      o["length"] = round_mm(s.size_m.z());
      break;
    case ShapeDesc::Kind::Sphere:
      o["shape"] = "sphere";
      o["radius"] = round_mm(s.size_m.x());
      break;
    case ShapeDesc::Kind::Mesh:
      o["shape"] = "mesh";
      put_mesh(s.mesh, o);
      break;
  }
  return o;
}

Json robot_of(const RobotDesc& r) {
  const ChassisDesc& c = r.chassis;
  Json body = {{"shape", "box"}, {"size", vec3(c.size_m)}};
  Json geoms = Json::array();
  if (c.shape == ChassisDesc::Shape::Parts) {
    for (const ShapeDesc& part : c.parts) {
      Json g = shape_of(part);
      g["part"] = "chassis";
      geoms.push_back(std::move(g));
    }
  } else {
    geoms.push_back({{"part", "chassis"}, {"shape", "box"}, {"pos", vec3(0, 0, 0)}, {"quat", quat(1, 0, 0, 0)},
                     {"size", vec3(c.size_m)}});
  }
  // A URDF's visuals, each on its body: -1 the chassis, else the wheel of that index.
  Json visuals = Json::array();
  for (const auto& v : r.urdf.visuals) {
    Json o = shape_of(v.shape);
    o["body"] = v.body;
    // A live joint's link moves on its own body: the frames give its pose.
    if (v.joint >= 0) {
      o["body"] = nullptr;
      o["joint"] = v.joint;
    }
    o["link"] = v.link;
    o["rgba"] = {v.rgba[0], v.rgba[1], v.rgba[2], v.rgba[3]};
    visuals.push_back(std::move(o));
  }
  for (const CasterDesc& k : r.casters)
    geoms.push_back({{"part", "caster"}, {"shape", "sphere"}, {"pos", vec3(k.position_m)}, {"quat", quat(1, 0, 0, 0)},
                     {"radius", round_mm(k.radius_m)}});
  // A tyre is a cylinder along the axle (robot y); a sphere of the same radius rolls on the ground.
  const Eigen::Quaterniond axle(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()));
  Json wheels = Json::array();
  for (const WheelDesc& w : r.wheels) {
    geoms.push_back({{"part", "wheel " + w.name}, {"shape", "cylinder"}, {"pos", vec3(w.position_m)}, {"quat", quat(axle)},
                     {"radius", round_mm(w.radius_m)}, {"length", round_mm(w.width_m)}});
    geoms.push_back({{"part", "tread " + w.name}, {"shape", "sphere"}, {"pos", vec3(w.position_m)},
                     {"quat", quat(1, 0, 0, 0)}, {"radius", round_mm(w.radius_m)}});
    wheels.push_back({{"name", w.name}, {"radius", round_mm(w.radius_m)}, {"width", round_mm(w.width_m)}});
  }
  // A URDF's live joints, each link with its physics shapes in its own body's frame.
  Json joints = Json::array();
  for (const JointLinkDesc& j : r.joints) {
    Json shapes = Json::array();
    for (const ShapeDesc& part : j.parts) shapes.push_back(shape_of(part));
    joints.push_back({{"name", j.joint},
                      {"link", j.link},
                      {"kind", j.kind == JointLinkDesc::Kind::Hinge ? "hinge" : "slider"},
                      {"geoms", std::move(shapes)}});
  }
  Json sensors = Json::array(), mcus = Json::array();
  for (const McuDesc& m : r.mcus) {
    const std::string id = r.name + "." + m.name;
    Json devices = Json::array();
    for (const DeviceDesc& d : m.devices) {
      sensors.push_back(sensor_of(d, id));
      Json device = {{"name", d.name}, {"element", d.kind ? d.kind->element : ""}, {"wiring", wiring_text(d)}};
      // The unit of each quantity the frames' readings and truth name, for the panel to label them
      // (a reading of the same quantity as the truth has its unit, reading_meaning.hpp).
      if (d.kind) {
        Json units = Json::object();
        for (const ReadingMeaning* meaning : {&reading_meaning(d.kind->element), &output_meaning(d.kind->element)})
          for (std::size_t i = 0; i < meaning->quantity.size() && i < meaning->unit.size(); ++i)
            units[meaning->quantity[i]] = meaning->unit[i];
        device["units"] = std::move(units);
      }
      devices.push_back(std::move(device));
    }
    for (const MotorWiring& w : m.motors)
      devices.push_back({{"name", w.motor}, {"element", "motor"},
                         {"wiring", "pwm " + std::to_string(w.pwm_pin) + ", dir " + std::to_string(w.dir_pin) +
                                        (w.brake_pin >= 0 ? ", brake " + std::to_string(w.brake_pin) : "")}});
    for (const ServoWiring& w : m.servos)
      devices.push_back({{"name", w.servo}, {"element", "servo"}, {"wiring", "pin " + std::to_string(w.pin)}});
    mcus.push_back({{"id", id}, {"console_uart", m.console_uart}, {"devices", std::move(devices)}});
  }
  Json robot = {{"name", r.name},     {"keyboard", r.mcus.empty()}, {"body", std::move(body)},       {"geoms", std::move(geoms)},
                {"wheels", wheels}, {"sensors", std::move(sensors)}, {"mcus", std::move(mcus)}};
  if (!visuals.empty()) robot["visuals"] = std::move(visuals);
  if (!joints.empty()) robot["joints"] = std::move(joints);
  return robot;
}

}  // namespace

SensorView sensor_view(const DeviceDesc& device) {
  if (!device.kind) return SensorView::None;
  const std::string element = device.kind->element;
  if (element == "gp2d12" || element == "gp2d15" || element == "hcsr04" || element == "maxbotix_lv_ez")
    return SensorView::Cone;
  if (element == "lms2xx") return SensorView::Fan;
  if (element == "ublox_neo6m" || element == "mtk3339") return SensorView::Gps;
  return SensorView::None;
}

std::string scene_json(const ProjectDesc& project) {
  const GeoPoint& o = project.world.gps_origin;
  Json world = {{"terrain", terrain_of(project)},
                {"obstacles", obstacles_of(project)},
                {"gps_origin", {{"latitude", o.latitude_deg}, {"longitude", o.longitude_deg}, {"altitude", o.altitude_m}}}};
  Json robots = Json::array();
  for (const RobotDesc& r : project.robots) robots.push_back(robot_of(r));
  const Json scene = {{"type", "scene"}, {"world", std::move(world)}, {"robots", std::move(robots)}};
  return scene.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace sear
