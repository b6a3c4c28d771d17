// Builds a firmware from its C sources with the system C compiler against the HAL, and keeps the
// executable in a cache keyed by everything that goes into it, so unchanged firmware is not rebuilt.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace sear {

struct FirmwareToolchain {
  std::string compiler;                 // one program, found on PATH: "cc" unless $CC names another
  std::string hal_include_dir;          // holds hal/*.h
  std::vector<std::string> libraries;   // static libraries to link, in order (the HAL runtime, device models)
  std::vector<std::string> link_flags;  // after the libraries, e.g. -lm
  std::string cache_dir;                // where built firmware is kept; created when missing
  // The language, optimisation and target flags; empty: the host build's (C99, -O2, warnings).
  std::vector<std::string> compile_flags;
  std::vector<std::string> extra_sources;  // compiled with every firmware: the AVR build's HAL
  std::string archiver;                    // when set, the extra sources are linked from an archive it makes
  std::string cxx_compiler;                // compiles .cpp/.cc/.cxx sources and links when there are any
  // One firmware's own build flags (<firmware defines includes flags c_std cxx_std>).
  std::vector<std::string> defines, include_dirs, extra_flags;
  std::string c_std, cxx_std;  // the firmware's: c99 / c++17 unless it names others (gnu99 / gnu++17 on the AVR)
  std::string hal_c_std;       // the extra sources' C, whatever the firmware's
  // Compile the firmware's own sources and stop: a check of what the compiler says, whose cached
  // "firmware" is an empty stamp. The extra sources are neither compiled nor linked, but their
  // folders stay on the include path, so the flags are the full build's.
  bool compile_only = false;
};

// what(): a first line naming the firmware, then the compiler's messages verbatim (they carry file:line).
struct FirmwareBuildError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A stop request (Ctrl-C, SIGTERM, SIGHUP) came while compiling: the compiler was killed and its
// scratch directory removed, so the next run compiles afresh.
struct FirmwareBuildInterrupted : FirmwareBuildError {
  FirmwareBuildInterrupted() : FirmwareBuildError("sear: interrupted while compiling firmware") {}
};

// compiler from $CC, else "cc"; cache_dir from $SEAR_CACHE_DIR, else $XDG_CACHE_HOME/sear/firmware,
// else $HOME/.cache/sear/firmware.
FirmwareToolchain default_toolchain(std::string hal_include_dir, std::vector<std::string> libraries,
                                    std::vector<std::string> link_flags = {});

// The ATmega2560 build for the AVR engine: avr-gcc ($AVR_CC names another) against the HAL of
// hal/targets/avr (its .c files in hal_avr_dir), F_CPU from the MCU's clock; the result is an ELF.
FirmwareToolchain avr_toolchain(std::string hal_include_dir, const std::string& hal_avr_dir, double clock_hz);

// Returns the path of an up-to-date executable built from `sources`, compiling only when a source, a
// header one of them includes, a library, the compiler or the flags changed. Concurrent calls, in this
// process or another, never see a half-written executable. When `compiler_output` is given it receives
// what the compiler said on a successful build (its warnings); it is left empty when nothing was built.
std::string build_firmware(const std::string& name, const std::vector<std::string>& sources,
                           const FirmwareToolchain& toolchain, std::string* compiler_output = nullptr);

// What the compiler said when it built the executable build_firmware() returned (its warnings),
// kept beside it in the cache: the same text on every run, whether or not this one compiled.
std::string cached_compiler_output(const std::string& executable);

}  // namespace sear
