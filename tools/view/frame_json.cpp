#include "view/frame_json.hpp"

#include <ode/ode.h>

#include <Eigen/Geometry>
#include <cmath>

#include "devices/beams.hpp"
#include "view/frame_round.hpp"

namespace sear {
namespace {

using Json = nlohmann::ordered_json;

Json mm_or_null(double v) { return std::isfinite(v) ? Json(round_mm(v)) : Json(); }

// Where the device sits in the world now: its mount point on the chassis.
Eigen::Vector3d mount_in_world(const Vehicle& v, const DeviceDesc& d) {
  dVector3 p;
  dBodyGetRelPointPos(v.chassis_body(), d.position_m.x(), d.position_m.y(), d.position_m.z(), p);
  return {p[0], p[1], p[2]};
}

}  // namespace

FrameWorld::FrameWorld(const ProjectDesc& project) : project_(project), plane_(project.world.gps_origin) {}

Json FrameWorld::sensor(const Simulation& sim, std::size_t robot, std::size_t mcu, std::size_t device,
                        const PanelDevice& panel) {
  const Vehicle& vehicle = sim.robot(robot);
  std::size_t m = mcu;
  for (std::size_t r = 0; r < robot; ++r) m -= project_.robots[r].mcus.size();
  const DeviceDesc& desc = project_.robots[robot].mcus[m].devices[device];
  Json s = {{"name", panel.name}};
  switch (panel.view) {
    case SensorView::Cone: {
      // The truth the model was fed, where it is a distance; a MaxBotix's sample is its noisy
      // reading in inches (and its serial half gets none), so its beam is cast here instead.
      if (panel.element != "maxbotix_lv_ez") {
        s["range_m"] = panel.has_truth ? mm_or_null(panel.truth[0]) : Json();
        break;
      }
      auto& caster = casters_[{mcu, device}];
      if (!caster) caster = std::make_unique<RangeSensor>(beam_of(desc));
      const RangeReading r = caster->measure(sim.physics(), vehicle.chassis_body(), vehicle.entity());
      s["range_m"] = r.hit ? Json(round_mm(r.distance_m)) : Json();
      break;
    }
    case SensorView::Fan: {
      const LmsScan& scan = panel.from_device->last_scan();
      if (scan.t_ns < 0) {
        s["ranges_m"] = Json();
        break;
      }
      Json ranges = Json::array();
      for (float v : scan.ranges_m) ranges.push_back(mm_or_null(v));
      s["start_deg"] = round_unit(scan.start_deg);
      s["step_deg"] = round_unit(scan.step_deg);
      s["scan_t"] = static_cast<double>(scan.t_ns) * 1e-9;
      s["ranges_m"] = std::move(ranges);
      break;
    }
    case SensorView::Gps: {
      const auto& fix = panel.from_device->last_position();
      if (fix) {
        GeoPoint p = *fix;
        if (std::isnan(p.altitude_m)) p.altitude_m = project_.world.gps_origin.altitude_m;
        const Enu e = plane_.to_enu(p);
        s["fix"] = vec3(e.east_m, e.north_m, e.up_m);
      } else {
        s["fix"] = Json();
      }
      const Eigen::Vector3d antenna = mount_in_world(vehicle, desc);
      s["truth"] = vec3(antenna.x(), antenna.y(), antenna.z());
      break;
    }
    case SensorView::None:
      break;
  }
  return s;
}

void FrameWorld::put(const Simulation& sim, const std::vector<McuPanel>& panels, Json& frame) {
  Json robots = Json::array();
  std::size_t mcu = 0;
  for (std::size_t r = 0; r < sim.robot_count() && r < project_.robots.size(); ++r) {
    const Vehicle& v = sim.robot(r);
    const VehicleState state = sim.robot_state(r);
    Json wheels = Json::array();
    for (std::size_t w = 0; w < v.wheel_count(); ++w)
      wheels.push_back({{"pos", vec3(dBodyGetPosition(v.wheel_body(w)))},
                        {"quat", quat(dBodyGetQuaternion(v.wheel_body(w)))},
                        {"radps", round_unit(v.wheel_speed(w))}});
    // A URDF's live links where their bodies are, and each joint's position (rad or m).
    Json joints = Json::array();
    for (std::size_t j = 0; j < v.joint_count(); ++j)
      joints.push_back({{"pos", vec3(dBodyGetPosition(v.joint(j).body()))},
                        {"quat", quat(dBodyGetQuaternion(v.joint(j).body()))},
                        {"q", round_unit(v.joint(j).position())}});
    Json sensors = Json::array();
    for (std::size_t m = 0; m < project_.robots[r].mcus.size(); ++m, ++mcu) {
      if (mcu >= panels.size()) break;
      const auto& devices = panels[mcu].devices();
      for (std::size_t d = 0; d < devices.size(); ++d)
        if (devices[d].view != SensorView::None) sensors.push_back(sensor(sim, r, mcu, d, devices[d]));
    }
    robots.push_back({{"name", project_.robots[r].name},
                      {"pos", vec3(state.position_m.x(), state.position_m.y(), state.position_m.z())},
                      {"quat", quat(dBodyGetQuaternion(v.chassis_body()))},
                      {"speed_mps", round_mm(state.forward_speed_mps)},
                      {"wheels", std::move(wheels)},
                      {"sensors", std::move(sensors)},
                      {"collisions", sim.tally(r).collisions}});
    if (!joints.empty()) robots.back()["joints"] = std::move(joints);
  }
  frame["robots"] = std::move(robots);

  // Boxes with a mass move when pushed; the static scenery is in the scene message only.
  Json obstacles = Json::array();
  const PhysicsWorld& physics = sim.physics();
  const dSpaceID space = physics.dynamic_space();
  for (int i = 0; i < dSpaceGetNumGeoms(space); ++i) {
    dGeomID g = dSpaceGetGeom(space, i);
    if (dGeomIsSpace(g) || !dGeomGetBody(g)) continue;
    const auto* tag = static_cast<const GeomTag*>(dGeomGetData(g));
    if (!tag || tag->role != GeomRole::Obstacle) continue;
    dQuaternion q;
    dGeomGetQuaternion(g, q);
    obstacles.push_back({{"name", physics.entity_names().at(static_cast<std::size_t>(tag->entity))},
                         {"pos", vec3(dGeomGetPosition(g))},
                         {"quat", quat(q)}});
  }
  frame["obstacles"] = std::move(obstacles);
}

}  // namespace sear
