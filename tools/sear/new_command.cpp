// `sear new DIR`: a working project from a template in assets/templates/ (firmware, project file
// with expectations, CMakeLists.txt for the simulator and the ATmega2560, the bundled rover).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <system_error>
#include <utility>

#include "sear/commands.hpp"
#include "sear/run_folder.hpp"

namespace sear {
namespace {

namespace fs = std::filesystem;

// Every template gets these too: the CMake build and a README, the same for all.
constexpr const char* kCommonFiles = "common";

// Every template drives the bundled rover. It is copied rather than referenced: the robot is part
// of the user's design (mass, wheel track, motors) and the project folder stays whole when it
// moves or goes into a repository of its own.
constexpr const char* kRobotFile = "robot.xml";

// A sketch template's sketch, written as <name>/<name>.ino as the Arduino IDE requires. Such a
// template brings its own README and .gitignore and no CMake build (the common files build C
// firmware).
constexpr const char* kSketchFile = "sketch.ino";

struct NewError {
  std::string message;
};

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw NewError{fmt::format("cannot read {}", path.string())};
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out.flush()) throw NewError{fmt::format("cannot write {}", path.string())};
}

std::string substitute(std::string text, const std::vector<std::pair<std::string, std::string>>& values,
                       const fs::path& source) {
  for (const auto& [key, value] : values) {
    for (std::size_t at = 0; (at = text.find(key, at)) != std::string::npos; at += value.size())
      text.replace(at, key.size(), value);
  }
  // A placeholder left over is a template naming something `sear new` does not know.
  std::smatch left;
  if (std::regex_search(text, left, std::regex("@[A-Z_]+@")))
    throw NewError{fmt::format("{}: unknown placeholder {}", source.string(), left.str())};
  return text;
}

// Regular files under `from`, as paths relative to it, sorted so that the report is stable.
std::vector<fs::path> template_files(const fs::path& from) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(from))
    if (entry.is_regular_file()) files.push_back(fs::relative(entry.path(), from));
  std::sort(files.begin(), files.end());
  return files;
}

// The project's name: given, or the folder's own. It names the project, the CMake project and
// target (so the .elf and .hex) and is printed by the firmware, so it keeps to what all accept.
std::string folder_name(const fs::path& dir) {
  const fs::path absolute = fs::absolute(dir).lexically_normal();
  return (absolute.has_filename() ? absolute : absolute.parent_path()).filename().string();
}

std::string project_name(const NewOptions& options, const fs::path& dir) {
  std::string name = options.name;
  if (name.empty()) name = folder_name(dir);
  if (!std::regex_match(name, std::regex("[A-Za-z][A-Za-z0-9_-]{0,63}")))
    throw NewError{fmt::format("'{}' cannot name a project: it must start with a letter and hold only letters, "
                               "digits, _ and - (at most 64){}",
                               name, options.name.empty() ? "; give one with --name" : "")};
  return name;
}

void check_empty_folder(const fs::path& dir) {
  std::error_code error;
  const auto status = fs::status(dir, error);
  if (!fs::exists(status)) return;
  if (!fs::is_directory(status))
    throw NewError{fmt::format("{} exists and is not a folder; sear new writes a new or empty folder", dir.string())};
  if (!fs::is_empty(dir))
    throw NewError{fmt::format("{} is not empty; sear new writes only into a new or empty folder, so that it never "
                               "overwrites a project",
                               dir.string())};
}

}  // namespace

std::vector<std::string> project_templates() {
  std::vector<std::string> names;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(SEAR_TEMPLATE_DIR, error))
    if (entry.is_directory() && entry.path().filename() != kCommonFiles)
      names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

int new_command(const NewOptions& options) {
  try {
    const fs::path dir = options.dir;
    const fs::path templates = SEAR_TEMPLATE_DIR;
    const fs::path chosen = templates / options.template_name;
    if (!fs::is_directory(chosen))
      throw NewError{fmt::format("no template '{}' in {}", options.template_name, templates.string())};
    const std::string name = project_name(options, dir);
    check_empty_folder(dir);

    const std::string link_flags = SEAR_NEW_FIRMWARE_LINK_FLAGS;
    const std::vector<std::pair<std::string, std::string>> values = {
        {"@NAME@", name},
        {"@TEMPLATE@", options.template_name},
        {"@OUT@", default_run_folder(name, false)},  // where `sear run .` writes
        {"@SEAR_SOURCE_DIR@", SEAR_SOURCE_DIR},
        {"@SEAR_HAL_LIBRARY@", SEAR_HAL_RUNTIME_LIBRARY},
        {"@SEAR_HAL_LINK_FLAGS@", link_flags.empty() ? link_flags : " " + link_flags},
    };
    fs::create_directories(dir);
    std::vector<std::string> written;
    const bool sketch = fs::exists(chosen / kSketchFile);
    std::vector<fs::path> sources = {chosen};
    if (!sketch) sources.insert(sources.begin(), templates / kCommonFiles);
    for (const fs::path& from : sources) {
      for (const fs::path& file : template_files(from)) {
        const fs::path to = file == kSketchFile ? fs::path(folder_name(dir) + ".ino") : file;
        fs::create_directories((dir / to).parent_path());
        write_file(dir / to, substitute(read_file(from / file), values, from / file));
        written.push_back(to.string());
      }
    }
    write_file(dir / kRobotFile, read_file(SEAR_NEW_ROBOT_FILE));
    written.push_back(kRobotFile);
    std::sort(written.begin(), written.end());

    const std::string shown = dir.string();
    fmt::print("sear new: wrote {} ({}, template {}): {}\n", shown, name, options.template_name,
               fmt::join(written, ", "));
    fmt::print("  run it:        sear run {}\n", shown);
    if (sketch) {
      fmt::print("  for the board: open {}/{}.ino in the Arduino IDE (Arduino Mega 2560)\n", shown, folder_name(dir));
      return 0;
    }
    fmt::print("  build it:      cmake -S {0} -B {0}/build && cmake --build {0}/build\n", shown);
    fmt::print("  for the chip:  cmake -S {0} -B {0}/build-avr -DCMAKE_TOOLCHAIN_FILE={1}/cmake/avr-gcc.cmake && "
               "cmake --build {0}/build-avr\n",
               shown, SEAR_SOURCE_DIR);
    return 0;
  } catch (const NewError& e) {
    fmt::print(stderr, "sear new: {}\n", e.message);
  } catch (const fs::filesystem_error& e) {
    fmt::print(stderr, "sear new: {}\n", e.what());
  }
  return 1;
}

}  // namespace sear
