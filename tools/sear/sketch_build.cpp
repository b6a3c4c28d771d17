// See sketch_build.hpp.
#include "sear/sketch_build.hpp"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace sear {

namespace {

std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Runs a command through the shell, returning its exit status and what it printed.
int run(const std::vector<std::string>& args, std::string& output) {
  std::string command;
  for (const auto& a : args) command += quoted(a) + " ";
  command += "2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return -1;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) output.append(buffer, n);
  const int status = ::pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A stable folder per sketch for arduino-builder's work, under the firmware cache.
std::string work_dir(const SketchToolchain& toolchain, const std::string& folder) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : folder) h = (h ^ c) * 1099511628211ull;
  return (fs::path(toolchain.firmware.cache_dir) / "sketches" /
          fmt::format("{}-{:016x}", fs::path(folder).filename().string(), h))
      .string();
}

// The include paths arduino-builder resolved (its includes.cache): the folders of the libraries the
// sketch uses, the core's and the variant's first.
std::vector<std::string> resolved_include_paths(const std::string& work) {
  std::ifstream in(fs::path(work) / "includes.cache");
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  static const std::regex kPath("\"Includepath\"\\s*:\\s*\"([^\"]*)\"");
  std::vector<std::string> paths;
  for (auto it = std::sregex_iterator(s.begin(), s.end(), kPath); it != std::sregex_iterator(); ++it)
    if (!(*it)[1].str().empty()) paths.push_back((*it)[1].str());
  return paths;
}

bool is_source(const fs::path& p) {
  const std::string e = p.extension().string();
  return e == ".c" || e == ".cpp" || e == ".cc";
}

// A library's sources as the IDE compiles them: src/ recursively (1.5 layout), or the folder's top
// level and utility/ (1.0 layout); examples and extras never.
void add_library_sources(const fs::path& include_path, std::vector<std::string>& sources) {
  const bool layout_15 = include_path.filename() == "src";
  std::error_code error;
  if (layout_15) {
    for (auto it = fs::recursive_directory_iterator(include_path, error); it != fs::recursive_directory_iterator(); ++it)
      if (it->is_regular_file() && is_source(it->path())) sources.push_back(it->path().string());
    return;
  }
  for (const auto& dir : {include_path, include_path / "utility"})
    for (const auto& entry : fs::directory_iterator(dir, error))
      if (entry.is_regular_file() && is_source(entry.path())) sources.push_back(entry.path().string());
}

std::string env_or(const char* name, const char* otherwise) {
  const char* value = std::getenv(name);
  return value && *value ? value : otherwise;
}

// The IDE's compile of the sketch for the Mega 2560 (Debian's platform.txt and boards.txt: the
// recipe's defines and flags, with -Wall as the host build has it), its core and variant first on
// the include path as arduino-builder resolved them. DECIMAL_DIG as hal/arduino/CMakeLists.txt says.
SketchChipBuild chip_build(const SketchToolchain& toolchain, const std::string& folder,
                           const std::vector<std::string>& sources, const std::vector<std::string>& include_paths) {
  SketchChipBuild chip;
  chip.sources = sources;
  FirmwareToolchain& t = chip.toolchain;
  t.compiler = env_or("AVR_CC", "avr-gcc");
  t.cxx_compiler = env_or("AVR_CXX", "avr-g++");
  t.c_std = t.hal_c_std = "gnu11";
  t.cxx_std = "gnu++11";
  t.hal_include_dir = toolchain.core_dir;
  t.cache_dir = toolchain.firmware.cache_dir;
  t.compile_only = true;
  t.compile_flags = {"-mmcu=atmega2560", "-DF_CPU=16000000L", "-DARDUINO=10807", "-DARDUINO_AVR_MEGA2560",
                     "-DARDUINO_ARCH_AVR", "-DDECIMAL_DIG=__DECIMAL_DIG__", "-Os", "-g", "-Wall", "-fpermissive",
                     "-fno-exceptions", "-fno-threadsafe-statics", "-Wno-error=narrowing"};
  for (const auto& include : include_paths) t.compile_flags.push_back("-I" + include);
  t.compile_flags.push_back("-I" + folder);
  return chip;
}

constexpr const char* kMegaFqbn = "arduino:avr:mega:cpu=atmega2560";

// arduino-builder doing `action` on the sketch in `folder`, as the IDE would: Debian's hardware and
// arduino-builder's own platform, then the libraries beside the sketch, then the user's.
std::vector<std::string> builder_args(const SketchToolchain& toolchain, const char* action, const std::string& folder,
                                      const std::vector<std::string>& library_dirs) {
  std::vector<std::string> args{toolchain.arduino_builder, action, "-quiet", "-hardware", toolchain.hardware_dir,
                                "-hardware", toolchain.builder_platform, "-tools", toolchain.builder_platform};
  std::error_code error;
  if (fs::is_directory(fs::path(folder) / "libraries", error))
    args.insert(args.end(), {"-libraries", (fs::path(folder) / "libraries").string()});
  for (const auto& dir : library_dirs) args.insert(args.end(), {"-libraries", fs::absolute(dir).string()});
  return args;
}

}  // namespace

std::string sketch_folder(const std::string& path) {
  fs::path p = fs::absolute(path).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();  // "Sketch/"
  std::error_code error;
  if (fs::is_regular_file(p, error) && p.extension() == ".ino") p = p.parent_path();
  if (!fs::is_directory(p, error))
    throw FirmwareBuildError(fmt::format("{}: error: not a sketch folder or .ino file", path));
  const fs::path main_ino = p / (p.filename().string() + ".ino");
  if (!fs::is_regular_file(main_ino, error))
    throw FirmwareBuildError(fmt::format("{}: error: a sketch folder holds a .ino named as the folder ({} is missing), "
                                         "as the Arduino IDE requires",
                                         path, main_ino.string()));
  return p.string();
}

SketchToolchain default_sketch_toolchain() {
  SketchToolchain t;
  t.hardware_dir = SEAR_ARDUINO_HARDWARE_DIR;
  t.builder_platform = SEAR_ARDUINO_BUILDER_PLATFORM_DIR;
  t.own_libraries_dir = SEAR_ARDUINO_OWN_LIBRARIES_DIR;
  t.core_dir = SEAR_ARDUINO_CORE_DIR;
  t.eeprom_dir = SEAR_ARDUINO_EEPROM_DIR;
  t.include_dirs = {SEAR_ARDUINO_INCLUDE_DIR, std::string(SEAR_ARDUINO_OWN_LIBRARIES_DIR) + "/Servo/src"};
  t.libraries = {SEAR_ARDUINO_LIBRARY, SEAR_ARDUINO_HAL_LIBRARY};
  // The sketch's .c files with the C compiler ($CC), the rest with the C++ one ($CXX), as the IDE.
  std::vector<std::string> link_flags{"-lm"};
#ifdef SEAR_FIRMWARE_SANITIZE
  // The Arduino layer and the HAL runtime were built with the sanitizers, so the sketch links their
  // runtime; its own code is compiled as it would be without them, as a native firmware's is.
  link_flags.push_back(SEAR_FIRMWARE_SANITIZE);
#endif
  t.firmware = default_toolchain(SEAR_ARDUINO_HAL_INCLUDE_DIR, {}, link_flags);
  t.firmware.cxx_std = "gnu++17";
  t.firmware.c_std = "gnu11";
  return t;
}

std::string build_sketch(const std::string& name, const std::string& path, const std::vector<std::string>& library_dirs,
                         const SketchToolchain& toolchain, std::string* compiler_output, SketchChipBuild* chip) {
  const std::string folder = sketch_folder(path);
  const std::string sketch_name = fs::path(folder).filename().string();
  const std::string work = work_dir(toolchain, folder);
  std::error_code error;
  fs::remove_all(work, error);  // arduino-builder keeps what it copied: a deleted tab must not linger
  fs::create_directories(work, error);

  // The IDE's preprocessing; libraries beside the sketch come first, then the user's, then ours.
  std::vector<std::string> args = builder_args(toolchain, "-preprocess", folder, library_dirs);
  args.insert(args.end(), {"-libraries", toolchain.own_libraries_dir, "-fqbn", kMegaFqbn, "-build-path", work,
                           (fs::path(folder) / (sketch_name + ".ino")).string()});
  std::string output;
  if (run(args, output) != 0)
    throw FirmwareBuildError(fmt::format("sketch '{}' failed to preprocess (arduino-builder):\n{}", folder, output));

  // The preprocessed .ino and the sketch's own .c/.cpp files, as arduino-builder copied them.
  std::vector<std::string> sources;
  for (const auto& entry : fs::directory_iterator(fs::path(work) / "sketch", error))
    if (entry.is_regular_file() && is_source(entry.path())) sources.push_back(entry.path().string());
  std::sort(sources.begin(), sources.end());

  if (chip) *chip = chip_build(toolchain, folder, sources, resolved_include_paths(work));

  // Libraries: each resolved folder outside Debian's hardware (whose core and AVR libraries the
  // layer replaces) and outside the layer's own (built into it) is compiled with the sketch.
  FirmwareToolchain firmware = toolchain.firmware;
  firmware.compile_flags = {"-O2", "-g", "-DARDUINO=10807", "-Wall"};
  for (const auto& dir : toolchain.include_dirs) firmware.compile_flags.push_back("-I" + dir);
  firmware.compile_flags.push_back("-I" + folder);
  const std::string hardware = fs::absolute(toolchain.hardware_dir).lexically_normal().string();
  const std::string own = fs::absolute(toolchain.own_libraries_dir).lexically_normal().string();
  std::set<std::string> seen;
  for (const auto& include : resolved_include_paths(work)) {
    const std::string dir = fs::absolute(include).lexically_normal().string();
    if (dir.rfind(hardware, 0) == 0 || dir.rfind(own, 0) == 0 || !seen.insert(dir).second) continue;
    firmware.compile_flags.push_back("-I" + dir);
    add_library_sources(dir, sources);
  }
  // Debian's core and EEPROM headers after the system's, as hal/arduino's CMakeLists.txt says why.
  firmware.compile_flags.insert(firmware.compile_flags.end(),
                                {"-idirafter", toolchain.core_dir, "-idirafter", toolchain.eeprom_dir});
  firmware.libraries = toolchain.libraries;
  return build_firmware(name, sources, firmware, compiler_output);
}

std::string build_avr_sketch(const std::string& path, const std::vector<std::string>& library_dirs,
                             const SketchToolchain& toolchain, double clock_hz) {
  const std::string folder = sketch_folder(path);
  const std::string sketch_name = fs::path(folder).filename().string();
  const std::string work = work_dir(toolchain, folder) + "-atmega2560";
  std::error_code error;
  fs::create_directories(work, error);
  const std::string dig = "-DDECIMAL_DIG=__DECIMAL_DIG__";  // Debian's avr-gcc 5.4: hal/arduino/CMakeLists.txt
  std::vector<std::string> args = builder_args(toolchain, "-compile", folder, library_dirs);
  args.insert(args.end(), {"-fqbn", kMegaFqbn,
                           fmt::format("-prefs=build.f_cpu={}L", static_cast<long long>(clock_hz)),
                           "-prefs=compiler.c.extra_flags=" + dig, "-prefs=compiler.cpp.extra_flags=" + dig,
                           "-build-path", work, (fs::path(folder) / (sketch_name + ".ino")).string()});
  std::string output;
  if (run(args, output) != 0)
    throw FirmwareBuildError(
        fmt::format("sketch '{}' failed to build for the ATmega2560 (arduino-builder, Debian's Arduino core):\n{}",
                    folder, output));
  const fs::path elf = fs::path(work) / (sketch_name + ".ino.elf");
  if (!fs::is_regular_file(elf, error))
    throw FirmwareBuildError(fmt::format("sketch '{}': arduino-builder made no {}:\n{}", folder, elf.string(), output));
  return elf.string();
}

}  // namespace sear
