// The table of device kinds as the loader and `sear sensors` read it: each kind's XML element,
// the MCU resources it is wired to, its parameters with units, defaults and ranges, and the
// factory that builds its running half (sim/devices). The rows are in sim/devices/device_kinds.cpp.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "scene/element_reader.hpp"

namespace sear {

struct DeviceDesc;
class SimDevice;
class DeviceHost;

// What a wiring attribute names on the MCU.
enum class WireKind {
  AdcChannel,  // 0..15; channel n is pin A<n> (54 + n)
  DevicePin,   // a pin the device drives (the MCU reads it)
  McuPin,      // a pin the firmware drives (the device reads it)
  UartPort,    // 0..3; the device talks on this port's RX and TX
  I2cAddress,  // 7-bit address on the MCU's I2C bus
};

// What the device needs of the firmware on a McuPin wire, for the run's wiring report
// (runtime/wiring_report.hpp): any output will do, pulses (a trigger), or a chip select that
// picks it for SPI transfers.
enum class WireUse { Output, Pulses, ChipSelect };

struct DeviceWire {
  const char* attribute;
  WireKind kind;
  bool required;
  const char* meaning;
  int fallback = -1;  // when absent and not required; -1: not wired
  WireUse use = WireUse::Output;
};

struct DeviceParam {
  enum class Type { Number, Whole, Choice, Name, Wheel /* one of the robot's wheels */ };
  const char* attribute;
  Type type;
  double fallback;  // in the file's unit; a Choice's index
  Range range;      // in the file's unit; unused for Choice and Name
  const char* unit; // "m", "deg" (held in radians), "V", "Hz", ... for messages and listings
  const char* meaning;
  std::vector<std::string> choices = {};  // Choice
  double to_si = 1;                        // file unit to SI: kDegToRad for degrees
  const char* fallback_text = nullptr;     // Name: the text when absent; null: required
};

// How a kind is placed on its robot.
enum class Mount { None, PositionYaw, PositionYawPitch, Full /* roll, pitch and yaw */ };

struct DeviceKind {
  const char* element;
  const char* summary;
  Mount mount;
  int link_inputs;  // inputs it takes in the link (its models in the firmware's process)
  std::vector<DeviceWire> wires;
  std::vector<DeviceParam> params;
  std::unique_ptr<SimDevice> (*make)(const DeviceDesc& desc, DeviceHost& host);
  // Checks that involve several values (at least one output wired, a beam's ray count); may be null.
  void (*check)(const DeviceDesc& desc, ElementReader& r) = nullptr;
};

// Every kind, in the order `sear sensors` lists them.
const std::vector<const DeviceKind*>& device_kinds();
const DeviceKind* find_device_kind(const std::string& element);

}  // namespace sear
