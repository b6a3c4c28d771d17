// Reads a robot's <mcu> elements: the firmware to run, the chip's clock and supply, and the wiring
// of its sensors and actuators to ADC channels, pins and UART ports; then cross-checks the wiring.
#include <fmt/format.h>
#include <tinyxml2.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <unordered_set>

#include "scene/loader_parts.hpp"
#include "scene/nearest_name.hpp"
#include "scene/uart_capture.hpp"
#include "scene/value_ranges.hpp"

namespace sear {
namespace {

// The reference board, an Arduino Mega 2560: pins 0..69, ADC channels 0..15, UARTs 0..3.
const Range kPin = Range::between(0, 69, "0..69 (the Mega 2560's pins; A0..A15 are 54..69)");
const Range kAdcChannel = Range::between(0, 15, "0..15");
const Range kUartPort = Range::between(0, 3, "0..3");

int read_index(ElementReader& r, const char* attribute, const Range& range, bool required) {
  // An absent optional index reads as -1, "not wired"; any number given must be in range.
  const auto v = required || r.has(attribute) ? r.required_number(attribute, range) : std::nullopt;
  if (!v) return -1;
  if (*v != std::floor(*v)) {
    r.error(fmt::format("<{}> '{}' must be a whole number in {}", r.name(), attribute, range.text));
    return -1;
  }
  return static_cast<int>(*v);
}

void read_mount(ElementReader& r, Eigen::Vector3d& position, double& yaw) {
  position = r.vec3("pos", position, ranges::kRobotXYZ);
  yaw = r.number("yaw_deg", 0.0, ranges::kYaw, "deg") * kDegToRad;
}

// The rays a beam of this half-angle and resolution casts, as sensors/range_sensor.cpp lays them
// out (the axis, then cones alpha, alpha - delta, ... each with rays at most delta apart). Worked
// out here too, so that `sear check` refuses a beam the run could not build.
double beam_ray_count(double half_angle, double resolution) {
  double total = 1;
  if (!(half_angle > 0)) return total;
  const double cones = std::ceil(half_angle / resolution - 1e-9);
  for (double k = 0; k < cones && total <= 1e6; ++k) {
    const double ratio = std::sin(0.5 * resolution) / std::sin(half_angle - k * resolution);
    total += ratio < 1 ? std::max(3.0, std::ceil(M_PI / std::asin(ratio) - 1e-9)) : 3.0;
  }
  return total;
}

// RangeSensor::kMaxRays: a typo in a resolution should not stall a run.
constexpr double kMaxBeamRays = 100000;

IrRangerDesc read_ranger(ElementReader& r, IrRangerDesc::Model model) {
  IrRangerDesc s;
  s.model = model;
  s.source = {r.file(), r.line()};
  s.name = r.required_text("name").value_or("");
  check_name(r, s.name);
  read_mount(r, s.position_m, s.yaw_rad);
  s.pitch_rad = r.number("pitch_deg", 0.0, ranges::kPitch, "deg") * kDegToRad;
  s.half_angle_rad = r.number("half_angle_deg", 2.0, ranges::kHalfAngle, "deg") * kDegToRad;
  s.resolution_rad = r.number("resolution_deg", 1.0, ranges::kResolution, "deg") * kDegToRad;
  if (const double rays = beam_ray_count(s.half_angle_rad, s.resolution_rad); rays > kMaxBeamRays)
    r.error(fmt::format("<{}> half_angle_deg {:g} with resolution_deg {:g} needs {} rays per measurement; at most {:.0f} "
                        "(use a coarser resolution_deg)",
                        r.name(), s.half_angle_rad / kDegToRad, s.resolution_rad / kDegToRad,
                        rays > 1e6 ? std::string("over 1000000") : fmt::format("{:.0f}", rays), kMaxBeamRays));
  s.max_range_m = r.number("max_range", 1.5, ranges::kMaxRange, "m");
  if (model == IrRangerDesc::Model::Gp2d12) {
    s.adc_channel = read_index(r, "adc", kAdcChannel, true);
    s.noise_sd_v = r.number("noise_v", 0.01, ranges::kNoiseV, "V");
  } else {
    s.pin = read_index(r, "pin", kPin, true);
    s.switch_distance_m = r.number("switch_distance", 0.24, ranges::kSwitchDistance, "m");
    s.hysteresis_m = r.number("hysteresis", s.hysteresis_m, ranges::kHysteresis, "m");
  }
  r.finish();
  return s;
}

BumpSwitchDesc read_bump(ElementReader& r) {
  BumpSwitchDesc b;
  b.source = {r.file(), r.line()};
  b.name = r.required_text("name").value_or("");
  check_name(r, b.name);
  read_mount(r, b.position_m, b.yaw_rad);
  b.pin = read_index(r, "pin", kPin, true);
  b.width_m = r.number("width", b.width_m, ranges::kBumpWidth, "m");
  b.reach_m = r.number("reach", b.reach_m, ranges::kBumpReach, "m");
  r.finish();
  return b;
}

MotorWiring read_motor_wiring(ElementReader& r) {
  MotorWiring m;
  m.source = {r.file(), r.line()};
  m.motor = r.required_text("name").value_or("");
  m.pwm_pin = read_index(r, "pwm", kPin, true);
  m.dir_pin = read_index(r, "dir", kPin, true);
  m.brake_pin = read_index(r, "brake", kPin, false);
  m.reversed = r.choice("reversed", {"false", "true"}, 0) == 1;
  r.finish();
  return m;
}

void read_firmware(ElementReader& r, McuDesc& mcu) {
  const bool has_exe = r.has("executable");
  const bool has_src = r.has("sources");
  if (has_exe == has_src) {
    r.error("<firmware> needs either 'executable' (a built firmware) or 'sources' (C files to compile)");
  } else if (has_exe) {
    const std::string written = r.text("executable", "");
    mcu.firmware_executable = path_beside(r.file(), written);
    // The run would fail only when it starts the process, after building everything else.
    if (check_readable_file(r, "firmware executable", written, mcu.firmware_executable) &&
        ::access(mcu.firmware_executable.c_str(), X_OK) != 0)
      r.error(fmt::format("<firmware> firmware executable '{}' is not executable ({}); chmod +x it, or name its "
                          "C files with 'sources'",
                          written, mcu.firmware_executable));
  } else {
    for (const auto& source : r.names("sources")) {
      const std::string path = path_beside(r.file(), source);
      // Each source is compiled on its own with -c: a header or any other file is no source,
      // and headers are found through #include.
      if (check_readable_file(r, "firmware source", source, path) &&
          std::filesystem::path(path).extension() != ".c")
        r.error(fmt::format("<firmware> firmware source '{}' is not a C source (a .c file); headers are found "
                            "through #include",
                            source));
      mcu.firmware_sources.push_back(std::filesystem::absolute(path).lexically_normal().string());
    }
    if (mcu.firmware_sources.empty()) r.error("<firmware> 'sources' names no files");
  }
  r.finish();
}

}  // namespace

void read_mcu(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics, McuDesc& mcu) {
  ElementReader r(&element, file, diagnostics);
  mcu.source = {file, r.line()};
  mcu.name = r.required_text("name").value_or("");
  check_name(r, mcu.name);
  mcu.clock_hz = r.number("clock_hz", mcu.clock_hz, ranges::kClock, "Hz");
  // A chip counts whole cycles.
  mcu.hal_call_cycles = r.whole_number("hal_call_cycles", mcu.hal_call_cycles, ranges::kHalCallCycles);
  mcu.avcc_v = r.number("avcc", mcu.avcc_v, ranges::kAvcc, "V");
  mcu.aref_v = r.number("aref", mcu.aref_v, ranges::kAref, "V");
  // -1: no console (no console.log is written).
  mcu.console_uart = static_cast<int>(
      r.whole_number("console_uart", 0, Range::between(-1, 3, "0..3, or -1 for no console")));
  check_at_most_one(element, file, diagnostics, {"firmware"});
  if (!element.FirstChildElement("firmware")) r.error("<mcu> needs a <firmware> naming its executable or sources");
  r.children({"firmware", "gp2d12", "gp2d15", "bump", "motor", "servo", "uart"},
             [&](const tinyxml2::XMLElement& child) {
               ElementReader c(&child, file, diagnostics);
               const std::string kind = child.Name();
               if (kind == "firmware") read_firmware(c, mcu);
               else if (kind == "gp2d12") mcu.rangers.push_back(read_ranger(c, IrRangerDesc::Model::Gp2d12));
               else if (kind == "gp2d15") mcu.rangers.push_back(read_ranger(c, IrRangerDesc::Model::Gp2d15));
               else if (kind == "bump") mcu.bumps.push_back(read_bump(c));
               else if (kind == "motor") mcu.motors.push_back(read_motor_wiring(c));
               else if (kind == "servo") {
                 ServoWiring s;
                 s.source = {file, c.line()};
                 s.servo = c.required_text("name").value_or("");
                 s.pin = read_index(c, "pin", kPin, true);
                 c.finish();
                 mcu.servos.push_back(s);
               } else {
                 UartDesc u;
                 u.source = {file, c.line()};
                 u.port = read_index(c, "port", kUartPort, true);
                 u.loopback = c.choice("loopback", {"false", "true"}, 0) == 1;
                 if (c.has("receive")) {
                   const std::string capture = c.text("receive", "");
                   const std::string path = path_beside(file, capture);
                   if (u.loopback) c.error("<uart> receives from its own TX (loopback) or from 'receive', not both");
                   else if (check_readable_file(c, "UART capture", capture, path))
                     u.receive = read_uart_capture(path, diagnostics);
                 }
                 c.finish();
                 mcu.uarts.push_back(u);
               }
             });
  r.finish();
}

void validate_mcus(const RobotDesc& robot, Diagnostics& diagnostics) {
  const auto fail = [&](const SourceRef& at, const std::string& message) {
    diagnostics.error(at.file, at.line, fmt::format("robot '{}': {}", robot.name, message));
  };
  // Hash sets keep the checks linear in the number of parts.
  std::vector<std::string> motor_names, servo_names;
  std::unordered_set<std::string> mcu_names;
  for (const auto& m : robot.motors) motor_names.push_back(m.name);
  for (const auto& s : robot.servos) servo_names.push_back(s.name);
  const std::unordered_set<std::string> motor_set(motor_names.begin(), motor_names.end());
  const std::unordered_set<std::string> servo_set(servo_names.begin(), servo_names.end());
  std::map<std::string, std::string> actuator_owner;  // one MCU (or the script) drives each actuator
  for (const auto& cmd : robot.script) actuator_owner.emplace(cmd.actuator, "the robot's <script>");

  for (const auto& mcu : robot.mcus) {
    if (!mcu_names.insert(mcu.name).second) fail(mcu.source, fmt::format("mcu name '{}' is used twice", mcu.name));
    std::map<int, std::string> pin_use, channel_use, port_use;
    std::unordered_set<std::string> part_names;
    const auto part = [&](const SourceRef& at, const std::string& name) {
      if (!part_names.insert(name).second) fail(at, fmt::format("mcu '{}' has two parts named '{}'", mcu.name, name));
    };
    const auto use = [&](std::map<int, std::string>& table, const char* what, int index, const SourceRef& at,
                         const std::string& user) {
      if (index < 0) return;
      const auto [it, fresh] = table.emplace(index, user);
      if (!fresh) fail(at, fmt::format("mcu '{}': {} {} is wired to both '{}' and '{}'", mcu.name, what, index, it->second, user));
    };
    for (const auto& s : mcu.rangers) {
      part(s.source, s.name);
      use(channel_use, "ADC channel", s.adc_channel, s.source, s.name);
      // ADC channel n is pin A<n> (54 + n): one pin, whichever way it is named.
      if (s.adc_channel >= 0) use(pin_use, "pin", 54 + s.adc_channel, s.source, s.name);
      use(pin_use, "pin", s.pin, s.source, s.name);
    }
    for (const auto& b : mcu.bumps) {
      part(b.source, b.name);
      use(pin_use, "pin", b.pin, b.source, b.name);
    }
    const auto own = [&](const SourceRef& at, const std::string& actuator) {
      const auto [it, fresh] = actuator_owner.emplace(actuator, "mcu '" + mcu.name + "'");
      if (!fresh) fail(at, fmt::format("'{}' is driven by both {} and mcu '{}'", actuator, it->second, mcu.name));
    };
    for (const auto& m : mcu.motors) {
      if (!motor_set.count(m.motor))
        fail(m.source, fmt::format("mcu '{}' wires unknown motor '{}'{}", mcu.name, m.motor,
                                   did_you_mean(diagnostics, m.motor, motor_names)));
      own(m.source, m.motor);
      use(pin_use, "pin", m.pwm_pin, m.source, "motor " + m.motor + " pwm");
      use(pin_use, "pin", m.dir_pin, m.source, "motor " + m.motor + " dir");
      use(pin_use, "pin", m.brake_pin, m.source, "motor " + m.motor + " brake");
    }
    for (const auto& s : mcu.servos) {
      if (!servo_set.count(s.servo))
        fail(s.source, fmt::format("mcu '{}' wires unknown servo '{}'{}", mcu.name, s.servo,
                                   did_you_mean(diagnostics, s.servo, servo_names)));
      own(s.source, s.servo);
      use(pin_use, "pin", s.pin, s.source, "servo " + s.servo);
    }
    for (const auto& u : mcu.uarts) use(port_use, "UART port", u.port, u.source, "a <uart>");
    constexpr std::size_t kMaxInputs = 32;  // SEAR_LINK_MAX_INPUTS: sensors the link carries per MCU
    if (mcu.rangers.size() + mcu.bumps.size() > kMaxInputs)
      fail(mcu.source, fmt::format("mcu '{}' has {} sensors; an MCU takes at most {}", mcu.name,
                                   mcu.rangers.size() + mcu.bumps.size(), kMaxInputs));
  }
}

}  // namespace sear
