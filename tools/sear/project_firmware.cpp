// Turns every MCU's <firmware sources="..."> into what its engine runs before a run, through the
// cached firmware builder: a host executable against the HAL runtime this `sear` was built with,
// or, on the AVR engine, an ATmega2560 image against hal/targets/avr, run by sear-avr-engine.
// A native MCU's sources are compiled for the ATmega2560 as well, meanwhile, for the chip's warnings.
#include <fmt/format.h>

#include <map>

#include "scene/description.hpp"
#include "sear/chip_check.hpp"
#include "sear/commands.hpp"
#include "sear/firmware_builder.hpp"
#ifdef SEAR_HAS_SKETCHES
#include "sear/sketch_build.hpp"
#endif

namespace sear {
namespace {

// The MCU's own build flags over a toolchain's defaults.
FirmwareToolchain with_flags(FirmwareToolchain toolchain, const McuDesc& mcu) {
  toolchain.defines = mcu.firmware_defines;
  toolchain.include_dirs = mcu.firmware_includes;
  toolchain.extra_flags = mcu.firmware_flags;
  if (!mcu.firmware_c_std.empty()) toolchain.c_std = mcu.firmware_c_std;
  if (!mcu.firmware_cxx_std.empty()) toolchain.cxx_std = mcu.firmware_cxx_std;
  return toolchain;
}

}  // namespace

void build_project_firmware(ProjectDesc& project, bool quiet) {
  std::vector<std::string> link_flags{"-lm"};
#ifdef SEAR_FIRMWARE_SANITIZE
  link_flags.push_back(SEAR_FIRMWARE_SANITIZE);
#endif
  const FirmwareToolchain toolchain =
      default_toolchain(SEAR_HAL_INCLUDE_DIR, {SEAR_HAL_RUNTIME_LIBRARY}, link_flags);

  // The chip's compile (the firmware's own sources, about 0.2 s each: the AVR HAL, 3 s more, is not
  // needed for warnings) starts first and goes on beside the host builds; its findings are printed
  // after theirs. Under --quiet nothing would be shown, so nothing is compiled.
  bool said_missing = false;
  const auto chip_compiler_found = [&said_missing](const std::string& compiler) {
    if (program_found(compiler)) return true;
    if (!said_missing)
      fmt::print(stderr, "sear: {} not found, so the firmware is not also compiled for the ATmega2560 to show what "
                         "only the chip's compiler sees, such as a 16-bit int overflowing (Debian: gcc-avr avr-libc)\n",
                 compiler);
    said_missing = true;
    return false;
  };
  std::future<std::vector<ChipOutcome>> chip_builds;
  try {
    std::vector<ChipFirmware> chip;
    for (const auto& robot : project.robots)
      for (const auto& mcu : robot.mcus)
        if (mcu.engine != "avr" && mcu.firmware_sketch.empty() && !mcu.firmware_sources.empty() && !quiet)
          chip.push_back({robot.name + "." + mcu.name, robot.name + "." + mcu.name + ".avr-check", mcu.firmware_sources,
                          with_flags(avr_toolchain(SEAR_HAL_INCLUDE_DIR, SEAR_HAL_AVR_DIR, mcu.clock_hz), mcu)});
    for (auto& one : chip) one.toolchain.compile_only = true;
    if (!chip.empty() && chip_compiler_found(chip.front().toolchain.compiler))
      chip_builds = start_chip_builds(std::move(chip));
  } catch (const FirmwareBuildError& e) {  // no AVR HAL beside this sear
    fmt::print(stderr, "sear: the firmware is not also compiled for the ATmega2560: {}\n", e.what());
  }
  // A sketch's is known once arduino-builder has preprocessed it, and compiled after every host
  // build, when no second build of the same sketch can replace its files any more (about 0.3 s).
  std::vector<ChipFirmware> sketch_chip;
  std::map<std::string, std::string> host_executables;  // by robot.mcu, for the chip's report
  for (auto& robot : project.robots) {
    for (auto& mcu : robot.mcus) {
      if (!mcu.firmware_sketch.empty()) {
#ifdef SEAR_HAS_SKETCHES
        if (mcu.engine == "avr") {  // the genuine core's build, what would be flashed
          const std::string elf = build_avr_sketch(mcu.firmware_sketch, mcu.firmware_sketch_libraries,
                                                   default_sketch_toolchain(), mcu.clock_hz);
          mcu.firmware_executable = SEAR_AVR_ENGINE;
          mcu.firmware_args = {"--clock-hz", fmt::format("{}", mcu.clock_hz), elf};
          continue;
        }
        std::string said;
        SketchChipBuild sketch;
        const std::string id = robot.name + "." + mcu.name;
        mcu.firmware_executable = build_sketch(id, mcu.firmware_sketch, mcu.firmware_sketch_libraries,
                                               default_sketch_toolchain(), &said, quiet ? nullptr : &sketch);
        if (!said.empty() && !quiet) fmt::print(stderr, "{}", said);
        if (!sketch.sources.empty()) {
          sketch_chip.push_back({id, id + ".avr-check", sketch.sources, sketch.toolchain});
          host_executables[id] = mcu.firmware_executable;
        }
        continue;
#else
        throw FirmwareBuildError(fmt::format("{}: error: this sear was built without the Arduino layer "
                                             "(arduino-core-avr and arduino-builder were missing)",
                                             mcu.firmware_sketch));
#endif
      }
      std::string warnings;
      if (mcu.engine == "avr") {
        std::string elf = mcu.firmware_elf;
        if (elf.empty())
          elf = build_firmware(robot.name + "." + mcu.name + ".avr", mcu.firmware_sources,
                               with_flags(avr_toolchain(SEAR_HAL_INCLUDE_DIR, SEAR_HAL_AVR_DIR, mcu.clock_hz), mcu),
                               &warnings);
        mcu.firmware_executable = SEAR_AVR_ENGINE;
        mcu.firmware_args = {"--clock-hz", fmt::format("{}", mcu.clock_hz), elf};
      } else if (!mcu.firmware_sources.empty()) {
        mcu.firmware_executable =
            build_firmware(robot.name + "." + mcu.name, mcu.firmware_sources, with_flags(toolchain, mcu), &warnings);
        host_executables[robot.name + "." + mcu.name] = mcu.firmware_executable;
      }
      if (!warnings.empty() && !quiet) fmt::print(stderr, "{}", warnings);
    }
  }
  std::vector<ChipOutcome> outcomes;
  if (chip_builds.valid()) outcomes = chip_builds.get();
  if (!sketch_chip.empty() && chip_compiler_found(sketch_chip.front().toolchain.cxx_compiler))
    for (auto& outcome : start_chip_builds(std::move(sketch_chip)).get()) outcomes.push_back(std::move(outcome));
  for (const auto& outcome : outcomes)
    fmt::print(stderr, "{}", chip_report(outcome, cached_compiler_output(host_executables[outcome.id])));
}

}  // namespace sear
