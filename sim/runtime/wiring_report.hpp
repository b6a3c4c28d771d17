// What a run can tell of wiring that does not match the firmware, once it is over: inputs a device
// expects that the firmware never drove, read or set up (a trigger never pulsed, an ADC channel
// never read, a port never begun), writes that only moved a pull-up, and pins the firmware drove
// that nothing is wired to. Each note names the MCU, the device and the pin.
#pragma once

#include <string>
#include <vector>

#include "runtime/mcu_bridge.hpp"

namespace sear {

struct WiringNote {
  enum class Kind {
    Unused,       // a device's input the firmware never drove, read or set up: likely a mistake
    InputWrite,   // a digital_write on a pin never made an OUTPUT: it only switched the pull-up
    UnwiredPin,   // a pin the firmware drove that nothing is wired to: fine for an LED
  };
  Kind kind;
  std::string mcu;     // "rover.main"
  std::string device;  // the device's or motor's name; empty for a bare pin
  int pin;             // the pin, ADC channel, port or I2C address the note is about
  std::string text;    // one line: "mcu rover.main: hcsr04 'sonar': its trig pin 22 was never ..."
};

// "unused wiring", "write to an input", "unwired output": summary.json's names.
const char* kind_name(WiringNote::Kind kind);

// The notes for one MCU at the end of its run, in the order of its devices, then by pin.
std::vector<WiringNote> wiring_notes(const McuBridge& mcu);

}  // namespace sear
