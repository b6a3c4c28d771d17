// Builds an Arduino sketch folder (issue 19) into a firmware for the simulator: the .ino files are
// preprocessed as the Arduino IDE does by Debian's arduino-builder (prototypes, #include <Arduino.h>,
// #line), the libraries it resolved (beside the sketch in libraries/, in the user's folders) are
// compiled with it, and the whole is built with the host's C++ compiler against the Arduino layer
// (hal/arduino) and the HAL runtime, through the cached firmware builder.
#pragma once

#include <string>
#include <vector>

#include "sear/firmware_builder.hpp"

namespace sear {

struct SketchToolchain {
  std::string arduino_builder = "arduino-builder";
  std::string hardware_dir;       // Debian's Arduino hardware folder (the AVR core and its libraries)
  std::string builder_platform;   // arduino-builder's own platform.txt folder (its ctags recipe)
  std::string own_libraries_dir;  // hal/arduino/libraries: the layer's libraries Debian lacks (Servo)
  std::string core_dir;           // Debian's core: Print.h, Stream.h, WString.h ...
  std::string eeprom_dir;         // Debian's EEPROM library, used unchanged
  std::vector<std::string> include_dirs;  // the layer's headers, before everything
  std::vector<std::string> libraries;     // the layer's library and the HAL runtime, in link order
  FirmwareToolchain firmware;             // compiler, cache and flags, as for C firmware
};

// This `sear`'s own: the paths it was built with, the compiler from $CXX (else c++), the cache of
// default_toolchain().
SketchToolchain default_sketch_toolchain();

// The folder a sketch path names: a folder holding <folder name>.ino, or that .ino file itself.
// Throws FirmwareBuildError naming the path when it is neither.
std::string sketch_folder(const std::string& path);

// What compiles the sketch for the ATmega2560 as the IDE does (chip_check.hpp): its own preprocessed
// files, against Debian's genuine AVR core and the libraries arduino-builder resolved, with avr-g++
// ($AVR_CXX; C files with $AVR_CC), the IDE's flags and -Wall, compile only.
struct SketchChipBuild {
  std::vector<std::string> sources;
  FirmwareToolchain toolchain;
};

// The executable built from the sketch at `path` (folder or .ino), searching `library_dirs` (and
// libraries/ beside the sketch) for the libraries it includes, as the IDE does. A library under
// Debian's AVR hardware folder (Wire, SPI, EEPROM, SoftwareSerial) is the layer's own instead.
// `chip`, when given, receives the sketch's ATmega2560 compile; its sources stay until the next
// build of the same sketch.
std::string build_sketch(const std::string& name, const std::string& path, const std::vector<std::string>& library_dirs,
                         const SketchToolchain& toolchain, std::string* compiler_output = nullptr,
                         SketchChipBuild* chip = nullptr);

// The sketch at `path` built for the ATmega2560 as the IDE builds it (arduino-builder -compile with
// Debian's genuine core and AVR libraries, the user's `library_dirs` and libraries/ beside the
// sketch), for the AVR engine at `clock_hz` (F_CPU); returns the .elf. arduino-builder keeps its
// work in a folder per sketch under the cache and rebuilds only what changed. The layer's own
// libraries (Servo) are host code and are not offered: a sketch needs the genuine one.
std::string build_avr_sketch(const std::string& path, const std::vector<std::string>& library_dirs,
                             const SketchToolchain& toolchain, double clock_hz);

}  // namespace sear
