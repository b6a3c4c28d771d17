// What a user described in project, world and robot files, after validation: plain data that
// the physics layer builds a live world from. Frames: world x east, y north, z up (ENU); robot
// x forward, y left, z up. Units SI (m, s, rad, kg, N*m); angles given in degrees in files are
// converted to radians here.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "scene/geodetic.hpp"

namespace sear {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

// Longest time a run or a scripted command may name: times become integer nanoseconds.
constexpr double kMaxTime_s = 1e7;
// Trace rates a run accepts, from one row a 100 s to one a microsecond.
constexpr double kMinTraceRate_hz = 0.01;
constexpr double kMaxTraceRate_hz = 1e6;

// Where a part was described, so that later checks can point at it.
struct SourceRef {
  std::string file;
  int line = 0;
};

// Triangles in metres, Z up, counter-clockwise seen from outside.
struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::uint32_t> indices;  // three per triangle
};

struct Material {
  std::string name;
  double friction = 0.8;  // Coulomb coefficient; a contact uses the lower of its two materials'
  double bounce = 0.0;    // restitution, 0..1
};

enum class TerrainKind { Flat, Heightmap, Mesh };

struct TerrainDesc {
  TerrainKind kind = TerrainKind::Flat;
  std::string material = "default";
  // Heightmap: `columns` x `rows` samples, row 0 is the north edge, heights in metres,
  // spanning size_m centred on the world origin.
  int columns = 0;
  int rows = 0;
  std::vector<double> heights_m;
  Eigen::Vector2d size_m{0, 0};
  TriangleMesh mesh;  // Mesh terrain, already in world coordinates
};

struct BoxDesc {
  std::string name;
  int line = 0;  // in the project file
  Eigen::Vector3d size_m{1, 1, 1};
  Eigen::Vector2d xy_m{0, 0};
  double z_m = 0;            // centre height; ignored when on_ground
  bool on_ground = true;     // rests on the terrain below its centre
  double yaw_rad = 0;
  double mass_kg = 0;        // 0: static
  std::string material = "default";
};

struct TreeDesc {
  std::string name;
  int line = 0;  // in the project file
  Eigen::Vector2d xy_m{0, 0};
  double trunk_radius_m = 0.1;
  double trunk_height_m = 2.0;
  double crown_radius_m = 0.8;  // a sphere centred on the top of the trunk
  std::string material = "default";
};

struct WallDesc {
  std::string name;
  int line = 0;  // in the project file
  Eigen::Vector2d from_m{0, 0};
  Eigen::Vector2d to_m{1, 0};
  double height_m = 1.0;
  double thickness_m = 0.1;
  std::string material = "default";
};

struct MeshObstacleDesc {
  std::string name;
  int line = 0;  // in the project file
  Eigen::Vector2d xy_m{0, 0};
  double yaw_rad = 0;
  TriangleMesh mesh;  // robot-independent, base at z = 0; placed on the terrain
  std::string material = "default";
};

struct WorldDesc {
  Eigen::Vector3d gravity{0, 0, -9.81};
  double step_s = 0.001;
  // How ODE solves each step's constraints (physics/constraint_solver). Direct (dWorldStep) solves
  // each group of touching bodies' rows exactly, at a cost that grows with the cube of the group's
  // rows: a robot's 20-40 rows cost less than QuickStep's 20 sweeps over them; a step with a larger
  // group, or one it gives up on, goes to the iterative solver. Iterative (dWorldQuickStep) sweeps
  // solver_iterations times, linear in the rows, and leaves static friction creeping (more
  // sweeps, less creep).
  enum class Solver { Direct, Iterative };
  Solver solver = Solver::Direct;
  int solver_iterations = 20;
  GeoPoint gps_origin{0, 0, 0};
  // The Earth's field as <magnetic> gives it; NaN: from the World Magnetic Model at the GPS origin.
  double magnetic_declination_rad = NAN;  // east of true north is positive
  double magnetic_inclination_rad = NAN;  // below the horizon is positive
  double magnetic_intensity_T = NAN;
  double magnetic_year = 2026.0;          // the decimal year the model is evaluated for
  std::vector<Material> materials;      // always holds "default"
  TerrainDesc terrain;
  std::vector<BoxDesc> boxes;
  std::vector<TreeDesc> trees;
  std::vector<WallDesc> walls;
  std::vector<MeshObstacleDesc> meshes;
};

enum class DriveKind { Differential, SkidSteer, Ackermann };

// A collision shape fixed to a body, placed in that body's frame (a URDF's <collision>).
struct ShapeDesc {
  enum class Kind { Box, Cylinder, Sphere, Mesh } kind = Kind::Box;
  Eigen::Vector3d position_m{0, 0, 0};
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d size_m{0, 0, 0};  // box: sides; cylinder: radius, radius, length along its z; sphere: radius x3
  TriangleMesh mesh;                // Mesh: in the shape's frame, metres
};

struct ChassisDesc {
  // Parts: the collision shapes in `parts` (a URDF's base and the links fixed to it).
  enum class Shape { Box, Mesh, Parts } shape = Shape::Box;
  Eigen::Vector3d size_m{0.3, 0.2, 0.08};  // box, or the mesh's bounding box once loaded
  double mass_kg = 1.0;
  std::string material = "default";
  TriangleMesh mesh;
  double bottom_z_m = -0.04;  // lowest point below the chassis origin (box: -size.z / 2)
  std::vector<ShapeDesc> parts;
  // A URDF's inertia about the chassis origin, which is then its centre of mass; else the box's.
  bool given_inertia = false;
  Eigen::Matrix3d inertia_kgm2 = Eigen::Matrix3d::Zero();
};

struct WheelDesc {
  std::string name;
  SourceRef source;
  Eigen::Vector3d position_m{0, 0, 0};  // axle centre in the robot frame
  double radius_m = 0.04;
  double width_m = 0.02;
  double mass_kg = 0.05;
  bool steered = false;  // Ackermann front wheels
  std::string material = "default";
  // From a URDF: inertia about the wheel's centre with z along the axle (else a uniform cylinder's),
  // and its joint's Coulomb friction and viscous damping.
  bool given_inertia = false;
  Eigen::Matrix3d inertia_kgm2 = Eigen::Matrix3d::Zero();
  double joint_friction_nm = 0;
  double joint_damping_nmps = 0;
};

// A URDF joint that moves and is no wheel: an ODE hinge (revolute, continuous) or slider
// (prismatic) between its parent's body and a body of its own, holding its child link and
// everything fixed below it. Passive unless a servo names it; its limits are stops, its
// dynamics a viscous and a Coulomb torque (or force).
struct JointLinkDesc {
  enum class Kind { Hinge, Slider } kind = Kind::Hinge;
  std::string joint, link;  // the URDF joint and its child link
  SourceRef source;         // the joint's line in the URDF
  int parent = -1;          // -1: the chassis, else an earlier entry of RobotDesc::joints
  // At rest (every joint at zero), in the robot frame: the body's centre of mass and axes, and
  // the joint's anchor and unit axis.
  Eigen::Vector3d position_m{0, 0, 0};
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d anchor_m{0, 0, 0};
  Eigen::Vector3d axis{1, 0, 0};
  double mass_kg = 0;
  Eigen::Matrix3d inertia_kgm2 = Eigen::Matrix3d::Zero();  // about the centre of mass, body axes
  std::vector<ShapeDesc> parts;                            // collision shapes in the body's frame
  std::string material = "default";
  bool limited = false;  // stops at lower and upper (rad or m)
  double lower = 0, upper = 0;
  double effort = 0;     // the URDF's <limit effort> (N*m or N), 0: none given
  double velocity = 0;   // the URDF's <limit velocity> (rad/s or m/s), 0: none given
  double damping = 0;    // N*m*s/rad or N*s/m
  double friction = 0;   // N*m or N
};

// A ball caster: rolls freely in every direction, so its contacts carry no friction.
struct CasterDesc {
  Eigen::Vector3d position_m{0, 0, 0};
  double radius_m = 0.02;
};

// A brushed DC gearmotor behind an H-bridge; figures at the gearbox output shaft, from the datasheet.
struct MotorDesc {
  std::string name;
  SourceRef source;
  // Several wheels share it as through an open differential: even torque split, mean speed.
  std::vector<std::string> wheels;
  double stall_torque_nm = 0.5;     // at rated_voltage_v
  double no_load_speed_radps = 20;  // at rated_voltage_v
  double rated_voltage_v = 6;       // the datasheet's test voltage (default: the supply voltage)
  double supply_voltage_v = 6;      // the H-bridge's supply; stall torque and free speed scale with it
  double gear_friction_nm = 0;  // Coulomb friction of the gearbox, holds the wheels when unpowered

  // Both ends of the torque-speed line scale with the voltage applied; its slope does not.
  double stall_torque_at_supply_nm() const { return stall_torque_nm * supply_voltage_v / rated_voltage_v; }
  double no_load_speed_at_supply_radps() const { return no_load_speed_radps * supply_voltage_v / rated_voltage_v; }
};

struct ServoDesc {
  enum class Kind { Positional, Continuous } kind = Kind::Positional;
  std::string name;
  SourceRef source;
  std::vector<std::string> wheels;  // continuous: the wheels it turns; positional: the wheels it steers
  std::string joint;                // or a URDF joint it turns (RobotDesc::joints), its neutral at the joint's zero
  double min_pulse_us = 1000;
  double max_pulse_us = 2000;
  double range_rad = 1.0;           // positional: travel between min and max pulse
  double speed_radps = 5.0;         // positional: slew rate; continuous: speed at full pulse
  double torque_nm = 0.3;           // stall torque
};

enum class MotorDirection { Forward, Reverse, Brake, Coast };

// One step of a robot's scripted command schedule.
struct ScriptCommand {
  SourceRef source;
  double t_s = 0;
  std::string actuator;
  bool is_servo = false;
  double duty = 0;  // motors, 0..1
  MotorDirection direction = MotorDirection::Forward;
  double pulse_us = 1500;  // servos
};

struct DeviceKind;

// A sensor or other device wired to an MCU, as its kind's row in the device table describes it
// (scene/device_kind.hpp): where it sits, what it is wired to, and its parameters.
struct DeviceDesc {
  const DeviceKind* kind = nullptr;
  std::string name;
  SourceRef source;
  Eigen::Vector3d position_m{0, 0, 0};  // robot frame
  double yaw_rad = 0;                   // counter-clockwise from the robot's x axis
  double pitch_rad = 0;                 // positive tilts the sensor's axis down
  double roll_rad = 0;                  // about its axis, right-handed
  std::vector<int> wires;               // per kind->wires: pin, channel, port or address; -1 not wired
  // Its UART wire given as "soft:RX,TX" (its wire then -1): the firmware's soft UART pins, RX the
  // one the device's TX drives, TX the one it listens to; -1 when on a port.
  int soft_rx_pin = -1;
  int soft_tx_pin = -1;
  std::vector<double> values;           // per kind->params, in SI units (Choice: the index)
  std::vector<std::string> texts;       // per kind->params: a Name's text, else empty

  // By attribute name; a name the kind does not have is a programming error (std::out_of_range).
  int wire(const char* attribute) const;
  double value(const char* attribute) const;
  const std::string& text(const char* attribute) const;
};

// A motor's H-bridge inputs on MCU pins: speed as PWM duty on `pwm_pin`, direction on `dir_pin`
// (HIGH forward unless `reversed`), and an optional brake pin (HIGH shorts the motor).
struct MotorWiring {
  std::string motor;
  SourceRef source;
  int pwm_pin = -1;
  int dir_pin = -1;
  int brake_pin = -1;
  bool reversed = false;
};

struct ServoWiring {
  std::string servo;
  SourceRef source;
  int pin = -1;
};

// A byte on a serial line, stamped with the end of its stop bit.
struct TimedByte {
  std::int64_t time_ns;
  std::uint8_t byte;
};

struct UartDesc {
  int port = 0;
  SourceRef source;
  bool loopback = false;            // TX wired to RX, as with a jumper on the bench
  std::vector<TimedByte> receive;   // bytes that arrive on RX at their times, from a capture
};

// A microcontroller on the robot: its firmware, clock, supply and everything wired to it.
struct McuDesc {
  std::string name;
  SourceRef source;
  std::string firmware_executable;            // absolute path, or empty when built from sources
  std::vector<std::string> firmware_sources;  // absolute paths of C files
  // "native" (the firmware as a host process) or "avr" (its AVR image on libsimavr, engines/avr)
  std::string engine = "native";
  std::string firmware_elf;                // engine "avr": the AVR image given, or empty to build it from sources
  std::vector<std::string> firmware_args;  // after the executable's name: the AVR engine's clock and image
  // How its sources are built, on either engine (<firmware defines includes flags c_std cxx_std>).
  std::vector<std::string> firmware_defines;   // NAME or NAME=VALUE, each a -D
  std::vector<std::string> firmware_includes;  // absolute folders, each a -I
  std::vector<std::string> firmware_flags;     // further compiler flags, as written
  std::string firmware_c_std;                  // for .c sources; empty: c99 (gnu99 for the AVR HAL's GNU C)
  std::string firmware_cxx_std;                // for .cpp sources; empty: c++17 (gnu++17 on the AVR)
  std::string firmware_sketch;                 // an Arduino sketch folder (absolute), or empty
  std::vector<std::string> firmware_sketch_libraries;  // the user's Arduino library folders, searched in order
  double clock_hz = 16e6;
  double hal_call_cycles = 50;  // what one HAL call costs on the chip
  double avcc_v = 5.0;
  double aref_v = 3.3;
  int console_uart = 0;
  std::vector<DeviceDesc> devices;  // in file order
  std::vector<MotorWiring> motors;
  std::vector<ServoWiring> servos;
  std::vector<UartDesc> uarts;
  std::string can_bus;  // the <can_bus> its CAN controller is on, empty: none
  SourceRef can_source;
  // <eeprom persist="true" file="...">: the file (absolute) its EEPROM is kept in from run to run;
  // empty: erased (0xFF) at each run. Without 'file', the project loader names it
  // ROBOT.MCU.eeprom beside the project file.
  bool eeprom_persist = false;
  std::string eeprom_file;
  SourceRef eeprom_source;
};

// What importing a URDF decided and saw, for `sear check` and the viewer.
struct UrdfImportDesc {
  std::string file;  // the URDF, empty for a robot written in SEAR's own files
  // base_link's origin in the chassis frame (the chassis origin is the lumped centre of mass).
  Eigen::Vector3d base_origin_m{0, 0, 0};
  struct Mesh {
    std::string link, use, file;  // use: "visual" or "collision"
    Eigen::Vector3d extent_m{0, 0, 0};
    std::size_t triangles = 0;
    std::string decision;  // what became of it: "trimesh", "box", "wheel cylinder", ...
  };
  std::vector<Mesh> meshes;
  // A visual, placed in the frame of its body (-1: the chassis, else a wheel's index; or, when
  // `joint` is not -1, the body of RobotDesc::joints[joint]).
  struct Visual {
    int body = -1;
    int joint = -1;
    std::string link;
    ShapeDesc shape;
    Eigen::Vector4d rgba{0.7, 0.7, 0.7, 1.0};
  };
  std::vector<Visual> visuals;
  std::vector<std::pair<SourceRef, std::string>> warnings;
  // What became of each joint that moves and is no wheel ("pan_joint: hinge, servo 'pan', ...").
  std::vector<std::string> joints;
};

struct RobotDesc {
  std::string name;
  SourceRef source;        // the <robot> element in the project
  SourceRef parts_source;  // where drive and parts are written: that element, or the robot file's root
  Eigen::Vector2d start_xy_m{0, 0};
  double start_yaw_rad = 0;  // counter-clockwise from east
  ChassisDesc chassis;
  DriveKind drive = DriveKind::Differential;
  std::vector<WheelDesc> wheels;
  std::vector<CasterDesc> casters;
  std::vector<JointLinkDesc> joints;  // a URDF's moving links that are no wheels, parents first
  std::vector<MotorDesc> motors;
  std::vector<ServoDesc> servos;
  std::vector<ScriptCommand> script;  // sorted by time
  std::vector<McuDesc> mcus;
  UrdfImportDesc urdf;
};

struct RunDesc {
  double duration_s = 30;
  std::uint64_t seed = 1;
  double trace_rate_hz = 100;
};

// A CAN bus between MCUs (of one robot or several), at one bit rate; SEAR itself may broadcast
// the robots' state on it (the frames tools/can/sear.dbc describes).
struct CanBusDesc {
  std::string name;
  SourceRef source;
  std::uint32_t bitrate = 500000;
  double broadcast_hz = 0;  // 0: SEAR sends nothing of its own
};

struct ProjectDesc {
  std::string file;
  std::string name;
  WorldDesc world;
  std::vector<RobotDesc> robots;
  std::vector<CanBusDesc> can_buses;
  RunDesc run;
};

}  // namespace sear
