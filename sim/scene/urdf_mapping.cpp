// Reads a project's <robot urdf="..."> and its mapping (what URDF cannot say: wheels, casters,
// motors, materials, device mounts), imports the URDF and fills a RobotDesc from both.
#include <fmt/format.h>
#include <tinyxml2.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "scene/device_kind.hpp"
#include "scene/loader_parts.hpp"
#include "scene/nearest_name.hpp"
#include "scene/robot_parts.hpp"
#include "scene/urdf_import.hpp"
#include "scene/urdf_joints.hpp"
#include "scene/value_ranges.hpp"

namespace sear {
namespace {

const Range kDensity = Range::above(0, 30000, "> 0 and <= 30000 kg/m^3 (osmium is 22590)");
const Range kTriangles = Range::between(1, 1e8, "1..1e8");
const Range kJointPosition = Range::between(-1e3, 1e3, "-1000..1000 (rad or m)");

// A device placed on a URDF link rather than at a position of its own.
struct DeviceMount {
  SourceRef source;
  std::string device, mcu, link;
  Eigen::Vector3d offset_m{0, 0, 0};
  double yaw_rad = 0, pitch_rad = 0, roll_rad = 0;
};

struct Mapping {
  UrdfMapping urdf;
  std::vector<DeviceMount> mounts;
  DriveKind drive = DriveKind::Differential;
};

// The mapping's own elements, in the project's <robot> or a mapping file's <urdf_mapping>.
void read_mapping_child(const tinyxml2::XMLElement& child, const std::string& file, Diagnostics& diagnostics,
                        WorldDesc& world, RobotDesc& robot, Mapping& mapping) {
  ElementReader c(&child, file, diagnostics);
  const std::string kind = child.Name();
  const SourceRef at{file, c.line()};
  UrdfMapping& m = mapping.urdf;
  if (kind == "material") {
    add_robot_material(c, world);
  } else if (kind == "package") {
    const std::string name = c.required_text("name").value_or("");
    const std::string dir = c.required_text("dir").value_or("");
    if (!dir.empty()) m.packages[name] = path_beside(file, dir);
  } else if (kind == "arg") {
    const std::string name = c.required_text("name").value_or("");
    m.args[name] = c.required_text("value").value_or("");
  } else if (kind == "wheel") {
    UrdfMapping::Wheel w;
    w.source = at;
    w.joint = c.required_text("joint").value_or("");
    w.name = c.text("name", w.joint);
    check_name(c, w.name);
    w.material = read_robot_material(c, world, diagnostics);
    m.wheels.push_back(w);
  } else if (kind == "caster") {
    UrdfMapping::Caster k;
    k.source = at;
    k.link = c.required_text("link").value_or("");
    k.radius_m = c.number("radius", 0.0, ranges::kWheelSize, "m");
    m.casters.push_back(k);
  } else if (kind == "freeze") {
    m.freezes.push_back({at, c.required_text("joint").value_or(""), c.number("position", 0.0, kJointPosition)});
  } else if (kind == "density") {
    UrdfMapping::Density d;
    d.source = at;
    d.link = c.text("link", "");
    d.kg_per_m3 = c.required_number("kg_per_m3", kDensity, "kg/m^3").value_or(1000);
    m.densities.push_back(d);
  } else if (kind == "collision") {
    UrdfMapping::Collision k;
    k.source = at;
    k.link = c.text("link", "");
    k.max_triangles = static_cast<std::size_t>(c.whole_number("max_triangles", 20000, kTriangles));
    k.replace = static_cast<UrdfMapping::Collision::Replace>(c.choice("replace", {"none", "box", "hull"}, 0));
    m.collisions.push_back(k);
  } else if (kind == "chassis") {
    m.chassis_material = read_robot_material(c, world, diagnostics);
  } else if (kind == "motor") {
    robot.motors.push_back(read_robot_motor(c));
  } else if (kind == "servo") {
    robot.servos.push_back(read_robot_servo(c));
  } else if (kind == "mount") {
    DeviceMount mount;
    mount.source = at;
    mount.device = c.required_text("device").value_or("");
    mount.mcu = c.text("mcu", "");
    mount.link = c.required_text("link").value_or("");
    mount.offset_m = c.vec3("pos", mount.offset_m, ranges::kRobotXYZ);
    mount.yaw_rad = c.number("yaw_deg", 0.0, ranges::kYaw, "deg") * kDegToRad;
    mount.pitch_rad = c.number("pitch_deg", 0.0, ranges::kPitch, "deg") * kDegToRad;
    mount.roll_rad = c.number("roll_deg", 0.0, ranges::kYaw, "deg") * kDegToRad;
    mapping.mounts.push_back(mount);
  }
  c.finish();
}

const std::vector<std::string> kMappingElements = {"material", "package", "arg",   "wheel", "caster", "freeze",
                                                   "density",  "collision", "chassis", "motor", "servo"};

// Devices sit where the mapping mounts them, or where their own `pos` says in base_link's frame;
// either way in the chassis frame afterwards, whose origin is the lumped centre of mass.
void place_devices(const Mapping& mapping, const UrdfRobot& urdf, Diagnostics& diagnostics, RobotDesc& robot) {
  std::vector<std::pair<DeviceDesc*, std::string>> devices;
  std::vector<std::string> names;
  for (auto& mcu : robot.mcus)
    for (auto& d : mcu.devices) {
      if (d.kind && d.kind->mount != Mount::None) d.position_m += urdf.report.base_origin_m;
      devices.push_back({&d, mcu.name});
      names.push_back(d.name);
    }
  std::vector<std::string> links;
  for (const auto& [name, frame] : urdf.links) links.push_back(name);
  for (const auto& m : mapping.mounts) {
    bool failed = false;
    const auto fail = [&](const std::string& message) {
      diagnostics.error(m.source.file, m.source.line, message);
      failed = true;
    };
    std::vector<DeviceDesc*> found;
    for (auto& [d, mcu] : devices)
      if (d->name == m.device && (m.mcu.empty() || m.mcu == mcu)) found.push_back(d);
    const auto link = urdf.links.find(m.link);
    if (found.empty()) fail(fmt::format("<mount> names unknown device '{}'{}", m.device, did_you_mean(diagnostics, m.device, names)));
    else if (found.size() > 1) fail(fmt::format("<mount> device '{}' is on more than one MCU: say which with 'mcu'", m.device));
    else if (link == urdf.links.end())
      fail(fmt::format("<mount> names link '{}', which the URDF does not have{}", m.link,
                       did_you_mean(diagnostics, m.link, links)));
    else if (!link->second.on_chassis)
      fail(fmt::format("<mount> link '{}' moves (with a wheel or a live joint); a device rides on the chassis", m.link));
    else if (found[0]->kind->mount == Mount::None)
      fail(fmt::format("<mount> device '{}' has no position to mount", m.device));
    if (failed) continue;
    DeviceDesc& d = *found[0];
    const Eigen::Matrix3d r = link->second.rotation * Eigen::AngleAxisd(m.yaw_rad, Eigen::Vector3d::UnitZ()) *
                              Eigen::AngleAxisd(m.pitch_rad, Eigen::Vector3d::UnitY()) *
                              Eigen::AngleAxisd(m.roll_rad, Eigen::Vector3d::UnitX());
    d.position_m = link->second.position_m + link->second.rotation * m.offset_m;
    // Z-Y-X angles; positive pitch turns the sensor's x axis down, as Ry(+pitch) does.
    d.yaw_rad = std::atan2(r(1, 0), r(0, 0));
    d.pitch_rad = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
    d.roll_rad = std::atan2(r(2, 1), r(2, 2));
  }
}

// Servos that name a URDF joint turn that live hinge: within the URDF's effort and velocity, if
// it gives them. `sear check` then prints what became of each live joint.
void attach_joint_servos(const UrdfRobot& urdf, Diagnostics& diagnostics, RobotDesc& robot) {
  std::vector<std::string> live;
  for (const auto& j : robot.joints) live.push_back(j.joint);
  std::vector<const ServoDesc*> turned_by(robot.joints.size(), nullptr);
  for (auto& s : robot.servos) {
    if (s.joint.empty()) continue;
    const auto it = std::find(live.begin(), live.end(), s.joint);
    if (it == live.end()) {
      diagnostics.error(s.source.file, s.source.line,
                        fmt::format("servo '{}' turns joint '{}', which is not a live joint of {} (a wheel's, a "
                                    "fixed or a held one, or none){}",
                                    s.name, s.joint, urdf.report.file, did_you_mean(diagnostics, s.joint, live)));
      continue;
    }
    const auto k = static_cast<std::size_t>(it - live.begin());
    const JointLinkDesc& j = robot.joints[k];
    if (j.kind == JointLinkDesc::Kind::Slider) {
      diagnostics.error(s.source.file, s.source.line,
                        fmt::format("servo '{}' turns joint '{}', which is prismatic: a servo turns, and SEAR has no "
                                    "linear actuator; the joint slides passively without it, or <freeze> holds it",
                                    s.name, s.joint));
      continue;
    }
    if (turned_by[k]) {
      diagnostics.error(s.source.file, s.source.line,
                        fmt::format("joint '{}' is already turned by servo '{}'", s.joint, turned_by[k]->name));
      continue;
    }
    if (j.effort > 0) s.torque_nm = std::min(s.torque_nm, j.effort);
    if (j.velocity > 0) s.speed_radps = std::min(s.speed_radps, j.velocity);
    turned_by[k] = &s;
  }
  for (std::size_t k = 0; k < robot.joints.size(); ++k)
    robot.urdf.joints.push_back(describe_joint(robot.joints[k], turned_by[k]));
}

}  // namespace

bool read_urdf_robot(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics,
                     WorldDesc& world, RobotDesc& robot, const UrdfOverrides& overrides) {
  ElementReader r(&element, file, diagnostics);
  robot.source = {file, r.line()};
  robot.parts_source = robot.source;
  robot.name = r.text("name", "");
  const std::string urdf_relative = r.required_text("urdf").value_or("");
  const std::string urdf_path = path_beside(file, urdf_relative);
  Mapping mapping;
  mapping.drive = static_cast<DriveKind>(r.choice("drive", {"differential", "skid_steer", "ackermann"}, 0));
  robot.drive = mapping.drive;

  // The mapping may stand in a file of its own (beside the URDF, say), read before the project's.
  const std::string mapping_relative = r.text("mapping", "");
  tinyxml2::XMLDocument mapping_doc;
  std::string mapping_text;
  if (!mapping_relative.empty()) {
    const std::string mapping_path = path_beside(file, mapping_relative);
    if (check_readable_file(r, "mapping file", mapping_relative, mapping_path) &&
        read_text_file(mapping_path, mapping_text) && parse_xml(mapping_text, mapping_path, diagnostics, mapping_doc)) {
      const tinyxml2::XMLElement* root = mapping_doc.RootElement();
      if (!root || std::string(root->Name()) != "urdf_mapping") {
        diagnostics.error(mapping_path, root ? root->GetLineNum() : 1,
                          "a URDF mapping file must have <urdf_mapping> as its root element");
      } else {
        ElementReader m(root, mapping_path, diagnostics);
        if (m.has("drive")) robot.drive = static_cast<DriveKind>(m.choice("drive", {"differential", "skid_steer", "ackermann"}, 0));
        m.children(kMappingElements, [&](const tinyxml2::XMLElement& child) {
          read_mapping_child(child, mapping_path, diagnostics, world, robot, mapping);
        });
        m.finish();
      }
    }
  }
  // Materials first: the wheels and chassis name them.
  for (auto* m = element.FirstChildElement("material"); m; m = m->NextSiblingElement("material")) {
    ElementReader c(m, file, diagnostics);
    add_robot_material(c, world);
  }
  check_at_most_one(element, file, diagnostics, {"pose", "script", "chassis"});
  std::vector<std::string> allowed = kMappingElements;
  for (const char* k : {"pose", "script", "mcu", "mount"}) allowed.emplace_back(k);
  r.children(allowed, [&](const tinyxml2::XMLElement& child) {
    const std::string kind = child.Name();
    if (kind == "material") return;
    if (kind == "pose") {
      ElementReader p(&child, file, diagnostics);
      read_robot_pose(p, world, robot);
    } else if (kind == "script") {
      read_script(child, file, diagnostics, robot.script);
    } else if (kind == "mcu") {
      robot.mcus.emplace_back();
      read_mcu(child, file, diagnostics, robot.mcus.back());
    } else {
      read_mapping_child(child, file, diagnostics, world, robot, mapping);
    }
  });
  r.finish();
  if (urdf_relative.empty() || !check_readable_file(r, "URDF", urdf_relative, urdf_path)) return false;

  for (const auto& [name, dir] : overrides.packages) mapping.urdf.packages[name] = dir;
  for (const auto& [name, value] : overrides.args) mapping.urdf.args[name] = value;
  UrdfRobot urdf;
  if (!import_urdf(urdf_path, mapping.urdf, diagnostics, urdf)) return false;
  if (robot.name.empty()) robot.name = urdf.name;
  robot.parts_source = {urdf_path, 1};
  robot.chassis = urdf.chassis;
  robot.wheels = urdf.wheels;
  robot.casters = urdf.casters;
  robot.joints = urdf.joints;
  robot.urdf = urdf.report;
  attach_joint_servos(urdf, diagnostics, robot);
  place_devices(mapping, urdf, diagnostics, robot);
  if (robot.name.empty()) r.error("<robot> needs a 'name' (here or in its URDF)");
  else check_name(r, robot.name);
  return true;
}

}  // namespace sear
