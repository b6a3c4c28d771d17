// `sear sensors`: every device kind a project's <mcu> can hold, read from the table of device
// kinds (sim/devices/device_kinds.cpp), so the listing is never out of step with the loader.
#include <fmt/format.h>

#include "sear/commands.hpp"
#include "scene/device_kind.hpp"
#include "scene/value_ranges.hpp"

namespace sear {
namespace {

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

const char* mount_text(Mount mount) {
  switch (mount) {
    case Mount::None: return "";
    case Mount::PositionYaw: return "pos, yaw_deg";
    case Mount::PositionYawPitch: return "pos, yaw_deg, pitch_deg";
    case Mount::Full: return "pos, yaw/pitch/roll_deg";
  }
  return "";
}

std::string default_text(const DeviceParam& p) {
  switch (p.type) {
    case DeviceParam::Type::Choice: {
      std::string all;
      for (std::size_t i = 0; i < p.choices.size(); ++i) all += (i ? " | " : "") + p.choices[i];
      return fmt::format("{} (default {})", all, p.choices.at(static_cast<std::size_t>(p.fallback)));
    }
    case DeviceParam::Type::Name: return p.fallback_text ? fmt::format("text (default {})", p.fallback_text) : "text, required";
    case DeviceParam::Type::Wheel: return "a wheel's name, required";
    default: return fmt::format("{:g} {} (default), {}", p.fallback, p.unit, p.range.text);
  }
}

}  // namespace

int sensors_command() {
  for (const DeviceKind* k : device_kinds()) {
    fmt::print("<{}>  {}\n", k->element, k->summary);
    fmt::print("    name                 required; letters, digits, _ and -\n");
    if (k->mount != Mount::None) fmt::print("    {:<20} where it sits on the chassis (robot frame)\n", mount_text(k->mount));
    for (const DeviceWire& w : k->wires)
      fmt::print("    {:<20} {}{}: {}\n", w.attribute, wire_text(w.kind), w.required ? ", required" : "", w.meaning);
    for (const DeviceParam& p : k->params) fmt::print("    {:<20} {}: {}\n", p.attribute, default_text(p), p.meaning);
    fmt::print("\n");
  }
  return 0;
}

}  // namespace sear
