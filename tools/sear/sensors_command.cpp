// `sear sensors`: every device kind a project's <mcu> can hold, read from the table of device
// kinds (sim/devices/device_kinds.cpp), so the listing is never out of step with the loader. As text
// for people, as JSON for tools, and as the Markdown reference docs/project.md holds between its markers.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cctype>
#include <string>
#include <vector>

#include "scene/device_kind.hpp"
#include "scene/value_ranges.hpp"
#include "sear/commands.hpp"

namespace sear {
namespace {

using Type = DeviceParam::Type;
// Keys in the order written (element first), as a person reading the listing expects them.
using Json = nlohmann::ordered_json;

// The placement attributes a mount reads. The table holds only the Mount value; these rows mirror
// read_device (sim/scene/mcu_loader.cpp), and tests/sensors_command_test.cpp holds them to it.
struct MountAttribute {
  const char* attribute;
  const char* unit;
  const Range* range;
  const char* meaning;
  bool vector = false;  // "x y z", each component in `range`
};

std::vector<MountAttribute> mount_attributes(Mount mount) {
  std::vector<MountAttribute> rows;
  if (mount == Mount::None) return rows;
  rows.push_back({"pos", "m", &ranges::kRobotXYZ, "where it sits on the chassis: \"x y z\" in the robot frame", true});
  rows.push_back({"yaw_deg", "deg", &ranges::kYaw, "turned counter-clockwise from the robot's x axis"});
  if (mount == Mount::PositionYawPitch || mount == Mount::Full)
    rows.push_back({"pitch_deg", "deg", &ranges::kPitch, "positive tilts its axis down"});
  if (mount == Mount::Full) rows.push_back({"roll_deg", "deg", &ranges::kYaw, "turned about its axis, right-handed"});
  return rows;
}

const char* wire_kind_name(WireKind kind) {
  switch (kind) {
    case WireKind::AdcChannel: return "adc_channel";
    case WireKind::DevicePin: return "device_pin";
    case WireKind::McuPin: return "mcu_pin";
    case WireKind::UartPort: return "uart_port";
    case WireKind::I2cAddress: return "i2c_address";
  }
  return "";
}

const char* wire_text(WireKind kind) {
  switch (kind) {
    case WireKind::AdcChannel: return "ADC channel";
    case WireKind::DevicePin: return "pin (device drives it)";
    case WireKind::McuPin: return "pin (firmware drives it)";
    case WireKind::UartPort: return "UART port";
    case WireKind::I2cAddress: return "I2C address";
  }
  return "";
}

const char* type_name(Type type) {
  switch (type) {
    case Type::Number: return "number";
    case Type::Whole: return "whole";
    case Type::Choice: return "choice";
    case Type::Name: return "text";
    case Type::Wheel: return "wheel";
  }
  return "";
}

bool required(const DeviceParam& p) { return p.type == Type::Wheel || (p.type == Type::Name && !p.fallback_text); }

// "2 deg", "9600": a number in the file's unit.
std::string with_unit(double value, const char* unit) {
  return *unit ? fmt::format("{:g} {}", value, unit) : fmt::format("{:g}", value);
}

std::string wire_default(const DeviceWire& w) {
  if (w.required) return "required";
  return w.fallback >= 0 ? fmt::format("{}", w.fallback) : "not wired";
}

std::string param_default(const DeviceParam& p) {
  switch (p.type) {
    case Type::Choice: return p.choices.at(static_cast<std::size_t>(p.fallback));
    case Type::Name: return p.fallback_text ? p.fallback_text : "required";
    case Type::Wheel: return "required";
    default: return with_unit(p.fallback, p.unit);
  }
}

// What the loader accepts, in words.
std::string param_accepts(const DeviceParam& p) {
  switch (p.type) {
    case Type::Choice: {
      std::string all;
      for (std::size_t i = 0; i < p.choices.size(); ++i) all += (i ? " | " : "") + p.choices[i];
      return all;
    }
    case Type::Name: return "text";
    case Type::Wheel: return "a wheel of the robot";
    case Type::Whole: return fmt::format("{}, whole", p.range.text);
    default: return p.range.text;
  }
}

Json range_json(const Range& r) {
  return {{"min", r.min}, {"max", r.max}, {"min_exclusive", r.min_exclusive}, {"text", r.text}};
}

Json kind_json(const DeviceKind& k) {
  Json mount = Json::array();
  for (const MountAttribute& m : mount_attributes(k.mount))
    mount.push_back({{"attribute", m.attribute},
                     {"type", m.vector ? "xyz" : "number"},
                     {"default", m.vector ? Json::array({0, 0, 0}) : Json(0)},
                     {"range", range_json(*m.range)},
                     {"unit", m.unit},
                     {"meaning", m.meaning}});
  Json wires = Json::array();
  for (const DeviceWire& w : k.wires)
    wires.push_back({{"attribute", w.attribute},
                     {"kind", wire_kind_name(w.kind)},
                     {"required", w.required},
                     {"meaning", w.meaning},
                     {"fallback", w.fallback >= 0 ? Json(w.fallback) : Json(nullptr)}});
  Json params = Json::array();
  for (const DeviceParam& p : k.params) {
    Json fallback = p.fallback;
    if (p.type == Type::Choice) fallback = p.choices.at(static_cast<std::size_t>(p.fallback));
    if (p.type == Type::Name) fallback = p.fallback_text ? Json(p.fallback_text) : Json(nullptr);
    if (p.type == Type::Wheel) fallback = nullptr;
    const bool numeric = p.type == Type::Number || p.type == Type::Whole;
    params.push_back({{"attribute", p.attribute},
                      {"type", type_name(p.type)},
                      {"required", required(p)},
                      {"default", fallback},
                      {"range", numeric ? range_json(p.range) : Json(nullptr)},
                      {"unit", p.unit},
                      {"choices", p.choices},
                      {"meaning", p.meaning}});
  }
  return {{"element", k.element}, {"summary", k.summary}, {"mount", mount}, {"wires", wires}, {"params", params}};
}

void print_text() {
  // 24 columns: the longest mount line, "pos, yaw/pitch/roll_deg", and a space.
  for (const DeviceKind* k : device_kinds()) {
    fmt::print("<{}>  {}\n", k->element, k->summary);
    fmt::print("    {:<24}required; letters, digits, _ and -\n", "name");
    for (const MountAttribute& m : mount_attributes(k->mount))
      fmt::print("    {:<24}{} (default {}), {}: {}\n", m.attribute, m.unit, m.vector ? "0 0 0" : "0", m.range->text,
                 m.meaning);
    for (const DeviceWire& w : k->wires) {
      const std::string how = w.required ? ", required" : w.fallback >= 0 ? fmt::format(" (default {})", w.fallback) : "";
      fmt::print("    {:<24}{}{}: {}\n", w.attribute, wire_text(w.kind), how, w.meaning);
    }
    for (const DeviceParam& p : k->params) {
      if (required(p)) fmt::print("    {:<24}{}, required: {}\n", p.attribute, param_accepts(p), p.meaning);
      else fmt::print("    {:<24}{} (default {}): {}\n", p.attribute, param_accepts(p), param_default(p), p.meaning);
    }
    fmt::print("\n");
  }
}

// Text in Markdown: '|' would end a table cell, and '<' before a letter, '/', '!' or '?' opens raw
// HTML or an autolink in CommonMark (R###<CR> would vanish); "<= 45" is left readable as it is.
std::string md(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char next = i + 1 < text.size() ? text[i + 1] : ' ';
    const bool opens = std::isalpha(static_cast<unsigned char>(next)) || next == '/' || next == '!' || next == '?';
    if (text[i] == '|') out += "\\|";
    else if (text[i] == '<' && opens) out += "&lt;";
    else out += text[i];
  }
  return out;
}


void print_markdown() {
  fmt::print(
      "\n### Sensors and devices in `<mcu>`\n\n"
      "Generated by `sear sensors --markdown` from the table the loader reads (`sim/devices`); "
      "`scripts/update-device-reference.sh` rewrites it. Every element also takes `name` (required: letters, "
      "digits, `_` and `-`). A wire names one of the MCU's ADC channels (channel n is pin A*n*, 54 + n), pins, "
      "UART ports or 7-bit I2C addresses; an optional wire left out is not wired. A UART wire takes a port "
      "0..3, or `soft:RX,TX`: the device on two plain pins of a soft UART, named as the firmware names them "
      "(`SoftwareSerial(RX, TX)`), its TX played out edge by edge on pin RX (a pin-change pin: 10..15, 50..53 "
      "or A8..A15, 62..69) and its RX decoded from pin TX ([docs/arduino.md](arduino.md#softwareserial)). "
      "Numbers are in the unit shown.\n");
  for (const DeviceKind* k : device_kinds()) {
    fmt::print("\n#### `<{}>`\n\n{}.\n\n", k->element, md(k->summary));
    fmt::print("| attribute | default | accepts | meaning |\n|---|---|---|---|\n");
    for (const MountAttribute& m : mount_attributes(k->mount))
      fmt::print("| `{}` | {} | {} | {} |\n", m.attribute, m.vector ? "0 0 0 m" : fmt::format("0 {}", m.unit),
                 md(m.vector ? fmt::format("each {}", m.range->text) : m.range->text), md(m.meaning));
    for (const DeviceWire& w : k->wires)
      fmt::print("| `{}` | {} | {} | {} |\n", w.attribute, wire_default(w), md(wire_text(w.kind)), md(w.meaning));
    for (const DeviceParam& p : k->params)
      fmt::print("| `{}` | {} | {} | {} |\n", p.attribute, md(param_default(p)), md(param_accepts(p)), md(p.meaning));
  }
  fmt::print("\n");
}

}  // namespace

int sensors_command(SensorsFormat format) {
  switch (format) {
    case SensorsFormat::Json: {
      Json all = Json::array();
      for (const DeviceKind* k : device_kinds()) all.push_back(kind_json(*k));
      fmt::print("{}\n", all.dump(2));
      break;
    }
    case SensorsFormat::Markdown: print_markdown(); break;
    case SensorsFormat::Text: print_text(); break;
  }
  return 0;
}

}  // namespace sear
