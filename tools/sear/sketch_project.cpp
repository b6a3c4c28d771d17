// `sear run path/to/Sketch/` (or its .ino) with no project.xml: the sketch runs on the default
// Arduino robot, the project `sear new --arduino` writes with the sketch in place of its own and
// without its expectations (which speak of the template's sketch).
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <regex>
#include <system_error>

#include "sear/commands.hpp"
#include "sear/firmware_builder.hpp"

namespace sear {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void replace_all(std::string& text, const std::string& key, const std::string& value) {
  for (std::size_t at = 0; (at = text.find(key, at)) != std::string::npos; at += value.size())
    text.replace(at, key.size(), value);
}

// XML text for an attribute value: a path may hold & or quotes.
std::string xml_escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

std::optional<std::string> sketch_default_project(const std::string& argument) {
  fs::path sketch_dir;
  const fs::path given(argument);
  if (given.extension() == ".ino" && fs::is_regular_file(given)) {
    sketch_dir = fs::absolute(given).lexically_normal().parent_path();
  } else if (fs::is_directory(given) && !fs::exists(given / "project.xml")) {
    const fs::path absolute = fs::absolute(given).lexically_normal();
    sketch_dir = absolute.has_filename() ? absolute : absolute.parent_path();
    if (!fs::is_regular_file(sketch_dir / (sketch_dir.filename().string() + ".ino"))) return std::nullopt;
  } else {
    return std::nullopt;
  }
  const std::string name = sketch_dir.filename().string();
  std::string project = read_text(fs::path(SEAR_TEMPLATE_DIR) / "arduino" / "project.xml");
  if (project.empty()) {
    fmt::print(stderr, "sear: the default Arduino robot ({}/arduino/project.xml) cannot be read\n", SEAR_TEMPLATE_DIR);
    return std::nullopt;
  }
  project = std::regex_replace(project, std::regex("\n\\s*<expect>[\\s\\S]*</expect>"), "");
  replace_all(project, "@NAME@", xml_escaped(name));
  replace_all(project, "file=\"robot.xml\"", "file=\"" + xml_escaped(SEAR_NEW_ROBOT_FILE) + "\"");
  replace_all(project, "sketch=\".\"", "sketch=\"" + xml_escaped(sketch_dir.string()) + "/\"");
  // Beside the firmware cache, one file per sketch folder, rewritten each time (same bytes for
  // the same folder, so runs stay the same).
  const fs::path dir = fs::path(default_toolchain("", {}).cache_dir) / "sketch-projects" /
                       fmt::format("{}-{:016x}", name, std::hash<std::string>{}(sketch_dir.string()));
  const fs::path file = dir / "project.xml";
  std::error_code error;
  fs::create_directories(dir, error);
  std::ofstream out(file, std::ios::binary);
  out << project;
  if (error || !out.flush()) {
    fmt::print(stderr, "sear: cannot write the default Arduino robot's project for {} to {}\n", sketch_dir.string(),
               file.string());
    return std::nullopt;
  }
  return file.string();
}

}  // namespace sear
