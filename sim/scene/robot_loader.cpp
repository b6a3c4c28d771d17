// Reads robots: a <robot> in a project, optionally including a reusable robot file, its pose,
// chassis, wheels, casters, motors, servos and scripted command schedule.
#include <fmt/format.h>
#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "scene/loader_parts.hpp"
#include "scene/mesh_loader.hpp"
#include "scene/nearest_name.hpp"
#include "scene/robot_parts.hpp"
#include "scene/value_ranges.hpp"

namespace sear {
namespace {

constexpr double kRpmToRadps = 2.0 * M_PI / 60.0;

std::vector<std::string> material_names(const WorldDesc& world) {
  std::vector<std::string> names;
  for (const auto& m : world.materials) names.push_back(m.name);
  return names;
}

bool has_material(const WorldDesc& world, const std::string& name) {
  return std::any_of(world.materials.begin(), world.materials.end(),
                     [&](const Material& m) { return m.name == name; });
}

std::string read_material(ElementReader& r, const WorldDesc& world, const Diagnostics& diagnostics) {
  const std::string name = r.text("material", "default");
  if (!has_material(world, name))
    r.error(fmt::format("<{}> uses unknown material '{}'{}", r.name(), name,
                        did_you_mean(diagnostics, name, material_names(world))));
  return name;
}

void read_chassis(ElementReader& r, const WorldDesc& world, const Diagnostics& diagnostics, ChassisDesc& chassis) {
  chassis.shape = r.choice("shape", {"box", "mesh"}, 0) == 0 ? ChassisDesc::Shape::Box : ChassisDesc::Shape::Mesh;
  chassis.mass_kg = r.required_number("mass", ranges::kChassisMass, "kg").value_or(chassis.mass_kg);
  chassis.material = read_material(r, world, diagnostics);
  if (chassis.shape == ChassisDesc::Shape::Box) {
    chassis.size_m = r.vec3("size", chassis.size_m, ranges::kChassisSide);
    chassis.bottom_z_m = -0.5 * chassis.size_m.z();
  } else {
    // The mesh's origin is taken as the chassis' centre of mass; its box gives size and inertia.
    Eigen::Vector3f lo = Eigen::Vector3f::Zero(), hi = Eigen::Vector3f::Zero();
    chassis.mesh = read_mesh_file(r, &lo, &hi);
    if (!chassis.mesh.indices.empty()) {
      chassis.size_m = (hi - lo).cast<double>();
      // The mesh's bounding box gives the chassis' inertia: a flat or tiny mesh would give none.
      if (!(chassis.size_m.minCoeff() >= ranges::kChassisSide.min && chassis.size_m.maxCoeff() <= ranges::kChassisSide.max))
        r.error(fmt::format("<chassis> mesh is {:.4g} x {:.4g} x {:.4g} m once scaled; each side must be in {}",
                            chassis.size_m.x(), chassis.size_m.y(), chassis.size_m.z(), ranges::kChassisSide.text));
      chassis.bottom_z_m = lo.z();
    }
  }
  r.finish();
}

WheelDesc read_wheel(ElementReader& r, const WorldDesc& world, const Diagnostics& diagnostics) {
  WheelDesc w;
  w.source = {r.file(), r.line()};
  w.name = r.required_text("name").value_or("");
  check_name(r, w.name);
  w.position_m = r.vec3("pos", w.position_m, ranges::kRobotXYZ);
  w.radius_m = r.required_number("radius", ranges::kWheelSize, "m").value_or(w.radius_m);
  w.width_m = r.number("width", w.width_m, ranges::kWheelSize, "m");
  w.mass_kg = r.number("mass", w.mass_kg, ranges::kWheelMass, "kg");
  w.steered = r.choice("steered", {"false", "true"}, 0) == 1;
  w.material = read_material(r, world, diagnostics);
  r.finish();
  return w;
}

MotorDesc read_motor(ElementReader& r) {
  MotorDesc m;
  m.source = {r.file(), r.line()};
  m.name = r.required_text("name").value_or("");
  check_name(r, m.name);
  m.wheels = r.names("wheels");
  if (m.wheels.empty()) r.error("<motor> needs attribute 'wheels' (the names of the wheels it drives)");
  m.stall_torque_nm = r.required_number("stall_torque", ranges::kStallTorque, "N*m").value_or(m.stall_torque_nm);
  if (r.has("no_load_rpm")) {
    m.no_load_speed_radps = r.number("no_load_rpm", m.no_load_speed_radps / kRpmToRadps, ranges::kNoLoadRpm, "rpm") *
                            kRpmToRadps;
  } else {
    m.no_load_speed_radps = r.required_number("no_load_speed", ranges::kNoLoadSpeed, "rad/s (or give no_load_rpm)")
                                .value_or(m.no_load_speed_radps);
  }
  // Without a rating the figures are taken as measured at the supply voltage.
  m.supply_voltage_v = r.number("supply_voltage", m.supply_voltage_v, ranges::kVoltage, "V");
  m.rated_voltage_v = r.number("rated_voltage", m.supply_voltage_v, ranges::kVoltage, "V");
  m.gear_friction_nm = r.number("gear_friction", m.gear_friction_nm, ranges::kGearFriction, "N*m");
  if (m.gear_friction_nm >= m.stall_torque_at_supply_nm())
    r.error("<motor> 'gear_friction' must be below the stall torque at the supply voltage, or the motor could never turn");
  r.finish();
  return m;
}

// `joints`: a URDF's mapping, where a servo may turn a joint instead of wheels.
ServoDesc read_servo(ElementReader& r, bool joints = false) {
  ServoDesc s;
  s.source = {r.file(), r.line()};
  s.name = r.required_text("name").value_or("");
  check_name(r, s.name);
  s.kind = r.choice("kind", {"positional", "continuous"}, 0) == 0 ? ServoDesc::Kind::Positional
                                                                   : ServoDesc::Kind::Continuous;
  if (joints && r.has("joint")) {
    s.joint = r.required_text("joint").value_or("");
    if (r.has(s.kind == ServoDesc::Kind::Positional ? "steers" : "wheels"))
      r.error("<servo> turns either a 'joint' or wheels, not both");
  } else {
    s.wheels = r.names(s.kind == ServoDesc::Kind::Positional ? "steers" : "wheels");
  }
  if (s.wheels.empty() && s.joint.empty())
    r.error(std::string(s.kind == ServoDesc::Kind::Positional ? "<servo kind=\"positional\"> needs 'steers' (wheel names)"
                                                              : "<servo kind=\"continuous\"> needs 'wheels' (wheel names)") +
            (joints ? " or 'joint' (a URDF joint it turns)" : ""));
  s.min_pulse_us = r.number("min_pulse_us", s.min_pulse_us, ranges::kPulse, "us");
  s.max_pulse_us = r.number("max_pulse_us", s.max_pulse_us, ranges::kPulse, "us");
  if (s.max_pulse_us <= s.min_pulse_us) r.error("<servo> 'max_pulse_us' must be above 'min_pulse_us'");
  s.torque_nm = r.number("torque", s.torque_nm, ranges::kServoTorque, "N*m");
  if (s.kind == ServoDesc::Kind::Positional) {
    s.range_rad = r.number("range_deg", 60.0, ranges::kServoTravel, "deg") * kDegToRad;
    // Hobby servo datasheets give speed as seconds per 60 degrees.
    const double s_per_60 = r.number("speed_s_per_60deg", 0.17, ranges::kServoSlew, "s");
    s.speed_radps = (60.0 * kDegToRad) / s_per_60;
  } else {
    s.speed_radps = r.number("no_load_rpm", 50.0, ranges::kServoRpm, "rpm") * kRpmToRadps;
  }
  r.finish();
  return s;
}

void read_pose(ElementReader& r, const WorldDesc& world, RobotDesc& robot) {
  const bool geo = r.has("latitude") || r.has("longitude");
  if (geo) {
    GeoPoint p;
    p.latitude_deg = r.required_number("latitude", ranges::kLatitude, "deg").value_or(0);
    p.longitude_deg = r.required_number("longitude", ranges::kLongitude, "deg").value_or(0);
    p.altitude_m = world.gps_origin.altitude_m;
    const Enu e = LocalTangentPlane(world.gps_origin).to_enu(p);
    robot.start_xy_m = {e.east_m, e.north_m};
    if (robot.start_xy_m.norm() > 100e3)
      r.error("<pose> is more than 100 km from the world's <gps_origin>; is the origin set?");
  } else {
    robot.start_xy_m = {r.number("x", 0.0, ranges::kWorldXY, "m"), r.number("y", 0.0, ranges::kWorldXY, "m")};
  }
  robot.start_yaw_rad = r.number("yaw_deg", 0.0, ranges::kYaw, "deg") * kDegToRad;
  r.finish();
}

// `inline_robot`: the parts stand in the project itself, which may also give the pose there.
void read_robot_parts(ElementReader& r, const tinyxml2::XMLElement& element, WorldDesc& world,
                      Diagnostics& diagnostics, RobotDesc& robot, bool inline_robot) {
  robot.drive = static_cast<DriveKind>(r.choice("drive", {"differential", "skid_steer", "ackermann"}, 0));
  // A reusable robot brings the materials of its tyres and chassis; a world that names the same
  // material keeps its own figures, since the world knows its surfaces.
  for (auto* m = element.FirstChildElement("material"); m; m = m->NextSiblingElement("material")) {
    ElementReader c(m, r.file(), diagnostics);
    const Material material = read_material_element(c);
    if (!material.name.empty() && !has_material(world, material.name)) world.materials.push_back(material);
  }
  check_at_most_one(element, r.file(), diagnostics, {"chassis", "pose", "script"});
  if (!element.FirstChildElement("chassis")) r.error("<robot> needs a <chassis>");
  const auto visit = [&](const tinyxml2::XMLElement& child) {
    ElementReader c(&child, r.file(), diagnostics);
    const std::string kind = child.Name();
    if (kind == "material") return;  // read above, before the parts that use them
    if (kind == "pose") read_pose(c, world, robot);
    else if (kind == "chassis") read_chassis(c, world, diagnostics, robot.chassis);
    else if (kind == "wheel") robot.wheels.push_back(read_wheel(c, world, diagnostics));
    else if (kind == "caster") {
      CasterDesc caster;
      caster.position_m = c.vec3("pos", caster.position_m, ranges::kRobotXYZ);
      caster.radius_m = c.required_number("radius", ranges::kWheelSize, "m").value_or(caster.radius_m);
      c.finish();
      robot.casters.push_back(caster);
    } else if (kind == "motor") robot.motors.push_back(read_motor(c));
    else if (kind == "servo") robot.servos.push_back(read_servo(c));
    else if (kind == "script") read_script(child, r.file(), diagnostics, robot.script);
    else if (kind == "mcu") {
      robot.mcus.emplace_back();
      read_mcu(child, r.file(), diagnostics, robot.mcus.back());
    }
  };
  if (inline_robot)
    r.children({"pose", "material", "chassis", "wheel", "caster", "motor", "servo", "script", "mcu"}, visit);
  else r.children({"material", "chassis", "wheel", "caster", "motor", "servo", "script"}, visit);
}

}  // namespace

// The parts a URDF's mapping shares with SEAR's own robot files (scene/robot_parts.hpp).
std::string read_robot_material(ElementReader& r, const WorldDesc& world, const Diagnostics& diagnostics) {
  return read_material(r, world, diagnostics);
}
MotorDesc read_robot_motor(ElementReader& r) { return read_motor(r); }
ServoDesc read_robot_servo(ElementReader& r) { return read_servo(r, true); }
void read_robot_pose(ElementReader& r, const WorldDesc& world, RobotDesc& robot) { read_pose(r, world, robot); }
void add_robot_material(ElementReader& r, WorldDesc& world) {
  const Material material = read_material_element(r);
  if (!material.name.empty() && !has_material(world, material.name)) world.materials.push_back(material);
}

void read_script(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics,
                 std::vector<ScriptCommand>& script) {
  ElementReader r(&element, file, diagnostics);
  script.clear();
  r.children({"motor", "servo"}, [&](const tinyxml2::XMLElement& child) {
    ElementReader c(&child, file, diagnostics);
    ScriptCommand cmd;
    cmd.source = {file, c.line()};
    cmd.t_s = c.required_number("t", ranges::kScriptTime, "s").value_or(0);
    cmd.actuator = c.required_text("name").value_or("");
    cmd.is_servo = std::string(child.Name()) == "servo";
    if (cmd.is_servo) {
      cmd.pulse_us = c.required_number("pulse_us", ranges::kPulse, "us").value_or(1500);
    } else {
      cmd.duty = c.number("duty", 0.0, ranges::kDuty);
      cmd.direction = static_cast<MotorDirection>(c.choice("dir", {"forward", "reverse", "brake", "coast"}, 0));
    }
    c.finish();
    script.push_back(cmd);
  });
  r.finish();
  std::stable_sort(script.begin(), script.end(),
                   [](const ScriptCommand& a, const ScriptCommand& b) { return a.t_s < b.t_s; });
}

bool read_project_robot(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics,
                        WorldDesc& world, RobotDesc& robot, const UrdfOverrides& overrides) {
  if (element.Attribute("urdf")) return read_urdf_robot(element, file, diagnostics, world, robot, overrides);
  bool parts_read = true;
  ElementReader r(&element, file, diagnostics);
  robot.source = {file, r.line()};
  robot.parts_source = robot.source;
  const std::string included = r.text("file", "");
  robot.name = r.text("name", "");

  if (!included.empty()) {
    // A reusable robot file: its <robot> holds the parts; the project adds pose and script.
    const std::string path = path_beside(file, included);
    tinyxml2::XMLDocument doc;
    std::string text;
    if (!check_readable_file(r, "robot file", included, path)) {
      parts_read = false;
    } else if (!read_text_file(path, text)) {
      parts_read = false;
      r.error(fmt::format("robot file '{}' cannot be read ({})", included, path));
    } else if (!parse_xml(text, path, diagnostics, doc)) {
      parts_read = false;
    } else if (!doc.RootElement() || std::string(doc.RootElement()->Name()) != "robot") {
      parts_read = false;
      diagnostics.error(path, doc.RootElement() ? doc.RootElement()->GetLineNum() : 1,
                        "a robot file must have <robot> as its root element");
    } else {
      ElementReader base(doc.RootElement(), path, diagnostics);
      robot.parts_source = {path, base.line()};
      const std::string base_name = base.text("name", "");
      if (robot.name.empty()) robot.name = base_name;
      read_robot_parts(base, *doc.RootElement(), world, diagnostics, robot, false);
      base.finish();
    }
    check_at_most_one(element, file, diagnostics, {"pose", "script"});
    // A <script> here replaces the robot file's: the project decides what this robot does, and
    // which firmware runs on it.
    r.children({"pose", "script", "mcu"}, [&](const tinyxml2::XMLElement& child) {
      if (std::string(child.Name()) == "script") {
        read_script(child, file, diagnostics, robot.script);
      } else if (std::string(child.Name()) == "mcu") {
        robot.mcus.emplace_back();
        read_mcu(child, file, diagnostics, robot.mcus.back());
      } else {
        ElementReader p(&child, file, diagnostics);
        read_pose(p, world, robot);
      }
    });
  } else {
    read_robot_parts(r, element, world, diagnostics, robot, true);
  }
  // A robot file that did not load already has its error; its name and parts are unknown, not wrong.
  if (parts_read && robot.name.empty()) r.error("<robot> needs a 'name' (here or in its robot file)");
  else if (parts_read) check_name(r, robot.name);
  r.finish();
  return parts_read;
}

}  // namespace sear
