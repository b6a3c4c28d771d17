// A native-engine run's look at the chip (issue 22): the firmware's own sources compiled for the
// ATmega2560 with avr-gcc, beside the host build and cached as it is, to show what only the chip's
// compiler says (an `int` of 16 bits overflowing). Never fails the run: what it finds goes to
// stderr, never into the run's files.
#pragma once

#include <future>
#include <string>
#include <vector>

#include "sear/firmware_builder.hpp"

namespace sear {

struct ChipFirmware {
  std::string id;    // robot.mcu, named in the messages
  std::string name;  // the cache's
  std::vector<std::string> sources;
  FirmwareToolchain toolchain;  // avr_toolchain() with the MCU's own flags, compile_only
};

struct ChipOutcome {
  std::string id;
  std::string compiler_output;  // what avr-gcc said when it compiled them (kept in the cache)
  std::string error;            // when they did not compile: FirmwareBuildError::what()
};

// Builds each firmware for the chip on a thread of its own, one after the other, so that the host
// builds go on meanwhile. Firmware with the same sources and flags is built and reported once.
// A stop request rethrows FirmwareBuildInterrupted from get().
std::future<std::vector<ChipOutcome>> start_chip_builds(std::vector<ChipFirmware> firmware);

// Whether `program` ("avr-gcc", or a path) can be run.
bool program_found(const std::string& program);

// The lines for stderr: each warning in `chip_output` that the host build (`host_output`) did not give
// at the same file, line and -W option, as "on the ATmega2560 (16-bit int): file:line:col: warning: ...",
// each once; or, for sources that do not compile, one line naming the first error.
std::string chip_report(const ChipOutcome& outcome, const std::string& host_output);

}  // namespace sear
