// Reads a robot's <mcu> elements: the firmware to run, the chip's clock and supply, and the wiring
// of its sensors and actuators to ADC channels, pins and UART ports; then cross-checks the wiring.
#include <fmt/format.h>
#include <tinyxml2.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <unordered_set>

#include "scene/board_pins.hpp"
#include "scene/device_kind.hpp"
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

// I2C addresses are 7 bits; 0..7 and 120..127 are reserved by the bus specification.
const Range kI2cAddress = Range::between(8, 119, "8..119 (7-bit; 0..7 and 120..127 are reserved)");

const Range& wire_range(WireKind kind) {
  switch (kind) {
    case WireKind::AdcChannel: return kAdcChannel;
    case WireKind::UartPort: return kUartPort;
    case WireKind::I2cAddress: return kI2cAddress;
    default: return kPin;
  }
}

// A UART wire given as "soft:RX,TX" puts the device on two plain pins of a soft UART, named as
// the firmware names them (SoftwareSerial(RX, TX)): false when the wire is a port number.
bool read_soft_uart(ElementReader& r, const DeviceWire& w, DeviceDesc& d) {
  if (w.kind != WireKind::UartPort || !r.has(w.attribute)) return false;
  const std::string text = r.text(w.attribute, "");
  if (text.rfind("soft:", 0) != 0) return false;
  int rx = -1, tx = -1;
  char extra = 0;
  const std::string wanted = fmt::format("<{}> '{}' \"{}\" must be soft:RX,TX: the firmware's receive and transmit "
                                         "pins, as in SoftwareSerial(RX, TX)", r.name(), w.attribute, text);
  if (std::sscanf(text.c_str() + 5, "%d,%d%c", &rx, &tx, &extra) != 2) {
    r.error(wanted);
    return true;
  }
  if (!kPin.contains(rx) || !kPin.contains(tx)) {
    r.error(fmt::format("{}; pins are {}", wanted, kPin.text));
    return true;
  }
  if (rx == tx) r.error(fmt::format("{}; RX and TX cannot be one pin", wanted));
  // The device's TX reaches the firmware only through a pin-change interrupt, as SoftwareSerial
  // receives on the Mega (hal/soft_uart.h): elsewhere nothing could ever be read.
  if (!mega2560_has_pin_change(rx))
    r.error(fmt::format("<{}> '{}' \"{}\": RX pin {} has no pin-change interrupt; a soft UART receives on 10..15, "
                        "50..53 and A8..A15 (62..69) of the Mega 2560",
                        r.name(), w.attribute, text, rx));
  d.soft_rx_pin = rx;
  d.soft_tx_pin = tx;
  return true;
}

// Any element in the device table: its name, mount, wiring and parameters as its row lists them.
DeviceDesc read_device(ElementReader& r, const DeviceKind& kind) {
  DeviceDesc d;
  d.kind = &kind;
  d.source = {r.file(), r.line()};
  d.name = r.required_text("name").value_or("");
  check_name(r, d.name);
  if (kind.mount != Mount::None) {
    d.position_m = r.vec3("pos", d.position_m, ranges::kRobotXYZ);
    d.yaw_rad = r.number("yaw_deg", 0.0, ranges::kYaw, "deg") * kDegToRad;
  }
  if (kind.mount == Mount::PositionYawPitch || kind.mount == Mount::Full)
    d.pitch_rad = r.number("pitch_deg", 0.0, ranges::kPitch, "deg") * kDegToRad;
  if (kind.mount == Mount::Full) d.roll_rad = r.number("roll_deg", 0.0, ranges::kYaw, "deg") * kDegToRad;
  for (const DeviceWire& w : kind.wires) {
    if (read_soft_uart(r, w, d)) {
      d.wires.push_back(-1);
      continue;
    }
    const int index = read_index(r, w.attribute, wire_range(w.kind), w.required);
    d.wires.push_back(index >= 0 || r.has(w.attribute) ? index : w.fallback);
  }
  for (const DeviceParam& p : kind.params) {
    double value = p.fallback;
    std::string text;
    switch (p.type) {
      case DeviceParam::Type::Number:
        value = r.number(p.attribute, p.fallback, p.range, p.unit);
        break;
      case DeviceParam::Type::Whole:
        value = r.whole_number(p.attribute, p.fallback, p.range);
        break;
      case DeviceParam::Type::Choice:
        value = static_cast<double>(r.choice(p.attribute, p.choices, static_cast<std::size_t>(p.fallback)));
        break;
      case DeviceParam::Type::Name:
      case DeviceParam::Type::Wheel:
        text = p.fallback_text ? r.text(p.attribute, p.fallback_text) : r.required_text(p.attribute).value_or("");
        break;
    }
    d.values.push_back(p.type == DeviceParam::Type::Choice ? value : value * p.to_si);
    d.texts.push_back(text);
  }
  if (kind.check) kind.check(d, r);
  r.finish();
  return d;
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

// How the firmware's sources are built (issue 21): defines, include folders, further flags and the
// language standards, the same for the native and the AVR build.
void read_build_flags(ElementReader& r, McuDesc& mcu) {
  const bool from_sources = !mcu.firmware_sources.empty();
  for (const char* attribute : {"defines", "includes", "flags", "c_std", "cxx_std"})
    if (r.has(attribute) && !from_sources)
      r.error(fmt::format("<firmware> '{}' is for firmware built from its 'sources'", attribute));
  for (const auto& define : r.names("defines")) {
    const std::string name = define.substr(0, define.find('='));
    const bool identifier = !name.empty() && !std::isdigit(static_cast<unsigned char>(name[0])) &&
                            std::all_of(name.begin(), name.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
    if (!identifier) r.error(fmt::format("<firmware> define '{}' is not NAME or NAME=VALUE (NAME a C identifier)", define));
    else mcu.firmware_defines.push_back(define);
  }
  for (const auto& folder : r.names("includes")) {
    const std::string path = path_beside(r.file(), folder);
    std::error_code error;
    if (!std::filesystem::is_directory(path, error))
      r.error(fmt::format("<firmware> include folder '{}' is not a folder ({})", folder, path));
    else mcu.firmware_includes.push_back(std::filesystem::absolute(path).lexically_normal().string());
  }
  for (const auto& flag : r.names("flags")) {
    // The builder names the output and the files itself; a flag that did so would break the cache.
    if (flag.empty() || flag[0] != '-' || flag == "-o" || flag == "-c" || flag.rfind("-std=", 0) == 0 ||
        flag.rfind("-M", 0) == 0)
      r.error(fmt::format("<firmware> flag '{}' is not one the builder can pass on (an option starting with '-'; not "
                          "-o, -c, -M..., and the standard goes in c_std or cxx_std)",
                          flag));
    else mcu.firmware_flags.push_back(flag);
  }
  if (r.has("c_std")) {
    mcu.firmware_c_std = r.text("c_std", "");
    static const char* const known[] = {"c89", "c99", "c11", "c17", "gnu89", "gnu99", "gnu11", "gnu17"};
    if (std::find(std::begin(known), std::end(known), mcu.firmware_c_std) == std::end(known))
      r.error(fmt::format("<firmware> c_std '{}' is not one of c89, c99, c11, c17, gnu89, gnu99, gnu11, gnu17",
                          mcu.firmware_c_std));
  }
  if (r.has("cxx_std")) {
    mcu.firmware_cxx_std = r.text("cxx_std", "");
    static const char* const known[] = {"c++11", "c++14", "c++17", "c++20", "gnu++11", "gnu++14", "gnu++17", "gnu++20"};
    if (std::find(std::begin(known), std::end(known), mcu.firmware_cxx_std) == std::end(known))
      r.error(fmt::format("<firmware> cxx_std '{}' is not one of c++11, c++14, c++17, c++20 (or their gnu++ forms)",
                          mcu.firmware_cxx_std));
  }
}

void read_firmware(ElementReader& r, McuDesc& mcu) {
  if (r.has("sketch")) {
    // An Arduino sketch folder (or its .ino), built against hal/arduino (docs/arduino.md).
    if (r.has("executable") || r.has("sources") || r.has("elf"))
      r.error("<firmware> names a 'sketch' alone: not with 'executable', 'sources' or 'elf'");
    const std::string written = r.text("sketch", "");
    mcu.firmware_sketch = std::filesystem::absolute(path_beside(r.file(), written)).lexically_normal().string();
    std::error_code error;
    if (!std::filesystem::exists(mcu.firmware_sketch, error))
      r.error(fmt::format("<firmware> sketch '{}' does not exist ({})", written, mcu.firmware_sketch));
    for (const auto& dir : r.names("libraries"))
      mcu.firmware_sketch_libraries.push_back(std::filesystem::absolute(path_beside(r.file(), dir)).string());
    r.finish();
    return;
  }
  const bool has_exe = r.has("executable");
  const bool has_src = r.has("sources");
  const bool has_elf = r.has("elf");
  if (has_elf && (has_exe || has_src)) {
    r.error("<firmware> names either 'elf' (an AVR image), 'executable' (a built firmware) or 'sources' (C files "
            "to compile), one of them");
  } else if (has_elf) {
    // The very image that would be flashed; it runs only on the AVR engine.
    const std::string written = r.text("elf", "");
    mcu.firmware_elf = path_beside(r.file(), written);
    check_readable_file(r, "AVR image", written, mcu.firmware_elf);
  } else if (has_exe == has_src) {
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
      const std::string ext = std::filesystem::path(path).extension().string();
      if (check_readable_file(r, "firmware source", source, path) && ext != ".c" && ext != ".cpp" && ext != ".cc" &&
          ext != ".cxx")
        r.error(fmt::format("<firmware> firmware source '{}' is not a C or C++ source (.c, .cpp, .cc, .cxx); headers "
                            "are found through #include",
                            source));
      mcu.firmware_sources.push_back(std::filesystem::absolute(path).lexically_normal().string());
    }
    if (mcu.firmware_sources.empty()) r.error("<firmware> 'sources' names no files");
  }
  read_build_flags(r, mcu);
  r.finish();
}

// <eeprom>: whether the EEPROM is kept from run to run, and in which file (docs/arduino.md).
void read_eeprom(ElementReader& r, McuDesc& mcu) {
  mcu.eeprom_source = {r.file(), r.line()};
  const bool has_file = r.has("file");
  const bool persist = r.choice("persist", {"false", "true"}, has_file ? 1 : 0) == 1;
  if (has_file && !persist) {
    r.error("<eeprom> 'file' keeps the EEPROM from run to run, which persist=\"false\" says not to do");
  } else if (has_file) {
    const std::string written = r.text("file", "");
    const std::string path = std::filesystem::absolute(path_beside(r.file(), written)).lexically_normal().string();
    std::error_code error;
    const auto folder = std::filesystem::path(path).parent_path();
    if (written.empty())
      r.error("<eeprom> 'file' is empty; leave it out for ROBOT.MCU.eeprom beside the project file");
    else if (std::filesystem::is_directory(path, error))
      r.error(fmt::format("<eeprom> file '{}' is a folder, expected a file ({})", written, path));
    else if (!std::filesystem::is_directory(folder, error))
      r.error(fmt::format("<eeprom> file '{}' is in a folder that does not exist ({})", written, folder.string()));
    mcu.eeprom_file = path;
  }
  mcu.eeprom_persist = persist;
  r.finish();
}

}  // namespace

void read_mcu(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics, McuDesc& mcu) {
  ElementReader r(&element, file, diagnostics);
  mcu.source = {file, r.line()};
  mcu.name = r.required_text("name").value_or("");
  check_name(r, mcu.name);
  mcu.clock_hz = r.number("clock_hz", mcu.clock_hz, ranges::kClock, "Hz");
  mcu.engine = r.choice("engine", {"native", "avr"}, 0) == 1 ? "avr" : "native";
  // A chip counts whole cycles.
  mcu.hal_call_cycles = r.whole_number("hal_call_cycles", mcu.hal_call_cycles, ranges::kHalCallCycles);
  mcu.avcc_v = r.number("avcc", mcu.avcc_v, ranges::kAvcc, "V");
  mcu.aref_v = r.number("aref", mcu.aref_v, ranges::kAref, "V");
  // -1: no console (no console.log is written).
  mcu.console_uart = static_cast<int>(
      r.whole_number("console_uart", 0, Range::between(-1, 3, "0..3, or -1 for no console")));
  check_at_most_one(element, file, diagnostics, {"firmware"});
  if (!element.FirstChildElement("firmware")) r.error("<mcu> needs a <firmware> naming its executable or sources");
  check_at_most_one(element, file, diagnostics, {"can", "eeprom"});
  std::vector<std::string> allowed = {"firmware", "motor", "servo", "uart", "can", "eeprom"};
  for (const DeviceKind* k : device_kinds()) allowed.emplace_back(k->element);
  r.children(allowed,
             [&](const tinyxml2::XMLElement& child) {
               ElementReader c(&child, file, diagnostics);
               const std::string kind = child.Name();
               if (kind == "firmware") read_firmware(c, mcu);
               else if (kind == "eeprom") read_eeprom(c, mcu);
               else if (const DeviceKind* device = find_device_kind(kind)) mcu.devices.push_back(read_device(c, *device));
               else if (kind == "motor") mcu.motors.push_back(read_motor_wiring(c));
               else if (kind == "can") {
                 // The bus is looked up once the whole project is read (project_loader.cpp).
                 mcu.can_source = {file, c.line()};
                 mcu.can_bus = c.required_text("bus").value_or("");
                 c.finish();
               }
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
  // Where each firmware can run: an AVR image needs the AVR engine, a prebuilt host executable the
  // native one; sources build for either.
  if (!mcu.firmware_elf.empty() && mcu.engine != "avr")
    r.error(fmt::format("<mcu> '{}': <firmware elf> is an AVR image, which runs only with engine=\"avr\"", mcu.name));
  if (!mcu.firmware_executable.empty() && mcu.engine == "avr")
    r.error(fmt::format("<mcu> '{}': engine=\"avr\" runs an AVR image: name it with <firmware elf> or give "
                        "'sources', not a host 'executable'",
                        mcu.name));
  r.finish();
}

void validate_mcus(const RobotDesc& robot, Diagnostics& diagnostics) {
  const auto fail = [&](const SourceRef& at, const std::string& message) {
    diagnostics.error(at.file, at.line, fmt::format("robot '{}': {}", robot.name, message));
  };
  // Hash sets keep the checks linear in the number of parts.
  std::vector<std::string> motor_names, servo_names, wheel_names;
  for (const auto& w : robot.wheels) wheel_names.push_back(w.name);
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
    std::map<int, std::string> address_use;
    std::size_t inputs = 0;
    for (const auto& d : mcu.devices) {
      part(d.source, d.name);
      inputs += static_cast<std::size_t>(d.kind->link_inputs);
      for (std::size_t i = 0; i < d.texts.size(); ++i)
        if (d.kind->params[i].type == DeviceParam::Type::Wheel &&
            std::find(wheel_names.begin(), wheel_names.end(), d.texts[i]) == wheel_names.end())
          fail(d.source, fmt::format("<{}> '{}' names unknown wheel '{}'{}", d.kind->element, d.name, d.texts[i],
                                     did_you_mean(diagnostics, d.texts[i], wheel_names)));
      for (std::size_t i = 0; i < d.wires.size(); ++i) {
        const int index = d.wires[i];
        switch (d.kind->wires[i].kind) {
          case WireKind::AdcChannel:
            use(channel_use, "ADC channel", index, d.source, d.name);
            // ADC channel n is pin A<n> (54 + n): one pin, whichever way it is named.
            if (index >= 0) use(pin_use, "pin", 54 + index, d.source, d.name);
            break;
          case WireKind::DevicePin:
          case WireKind::McuPin:
            use(pin_use, "pin", index, d.source, d.name);
            break;
          case WireKind::UartPort:
            use(port_use, "UART port", index, d.source, d.name);
            if (d.soft_rx_pin >= 0) {  // a soft UART: two pins, and the model playing its frames out
              use(pin_use, "pin", d.soft_rx_pin, d.source, d.name);
              use(pin_use, "pin", d.soft_tx_pin, d.source, d.name);
              ++inputs;
            }
            break;
          case WireKind::I2cAddress:
            use(address_use, "I2C address", index, d.source, d.name);
            break;
        }
      }
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
      // The firmware's pwm_write() on such a pin stops it, so the run would end at its first drive.
      if (m.pwm_pin >= 0 && !mega2560_has_pwm(m.pwm_pin))
        fail(m.source, fmt::format("mcu '{}': motor '{}' has pwm=\"{}\", a pin with no PWM on the ATmega2560; "
                                   "its PWM pins are {}",
                                   mcu.name, m.motor, m.pwm_pin, mega2560_pwm_pins()));
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
    constexpr std::size_t kMaxInputs = 32;  // SEAR_LINK_MAX_INPUTS: device models the link carries per MCU
    if (inputs > kMaxInputs)
      fail(mcu.source, fmt::format("mcu '{}' has {} sensors served in its process; an MCU takes at most {}", mcu.name,
                                   inputs, kMaxInputs));
  }
}

}  // namespace sear
