// A sensor placed far outside the robot that carries it: loads, but is almost always a position
// in centimetres written as metres, which leaves the sensor looking at the world from metres away.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "scene/device_kind.hpp"
#include "scene/loader_parts.hpp"

namespace sear {
namespace {

// A mast or a boom a few body sizes long is real; a centimetre figure read as metres is 100 times
// too far. Five times the body's reach lies between the two by a factor of 5 to 20 either way.
constexpr double kFarFactor = 5;

double shape_reach_m(const ShapeDesc& s) {
  switch (s.kind) {
    case ShapeDesc::Kind::Box: return s.position_m.norm() + 0.5 * s.size_m.norm();
    case ShapeDesc::Kind::Cylinder: return s.position_m.norm() + std::hypot(s.size_m.x(), 0.5 * s.size_m.z());
    case ShapeDesc::Kind::Sphere: return s.position_m.norm() + s.size_m.x();
    case ShapeDesc::Kind::Mesh: break;
  }
  double reach = 0;
  for (const auto& v : s.mesh.vertices) reach = std::max(reach, (s.position_m + s.rotation * v.cast<double>()).norm());
  return reach;
}

}  // namespace

double robot_reach_m(const RobotDesc& robot) {
  const ChassisDesc& c = robot.chassis;
  double reach = 0;
  switch (c.shape) {
    case ChassisDesc::Shape::Box: reach = 0.5 * c.size_m.norm(); break;
    case ChassisDesc::Shape::Mesh:
      for (const auto& v : c.mesh.vertices) reach = std::max(reach, v.cast<double>().norm());
      break;
    case ChassisDesc::Shape::Parts:
      for (const auto& p : c.parts) reach = std::max(reach, shape_reach_m(p));
      break;
  }
  for (const auto& w : robot.wheels) reach = std::max(reach, w.position_m.norm() + w.radius_m);
  for (const auto& k : robot.casters) reach = std::max(reach, k.position_m.norm() + k.radius_m);
  return reach;
}

void warn_misplaced_devices(const RobotDesc& robot, Diagnostics& diagnostics) {
  const double reach = robot_reach_m(robot);
  if (!(reach > 0)) return;
  for (const auto& mcu : robot.mcus)
    for (const auto& d : mcu.devices) {
      if (d.kind->mount == Mount::None) continue;
      const double distance = d.position_m.norm();
      if (distance <= kFarFactor * reach) continue;
      diagnostics.warning(d.source.file, d.source.line,
                          fmt::format("robot '{}': <{}> '{}' at pos=\"{:g} {:g} {:g}\" is {:.3g} m from the robot's "
                                      "origin, while the robot itself reaches {:.3g} m from it: 'pos' is in metres "
                                      "(centimetres written as metres?)",
                                      robot.name, d.kind->element, d.name, d.position_m.x(), d.position_m.y(),
                                      d.position_m.z(), distance, reach));
    }
}

}  // namespace sear
