#include "sear/urdf_options.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <filesystem>

namespace sear {
namespace {

namespace fs = std::filesystem;

// NAME=VALUE with a name; for --package the value a folder that exists. CLI11 puts the option's
// name before the message.
CLI::Validator name_value(const std::string& value_name, bool folder) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        const auto eq = text.find('=');
        if (eq == std::string::npos) return fmt::format("expected NAME={}, got '{}' (no '=')", value_name, text);
        if (eq == 0) return fmt::format("expected NAME={}, got '{}' (the name is empty)", value_name, text);
        if (folder) {
          const std::string dir = text.substr(eq + 1);
          std::error_code ec;
          if (dir.empty()) return fmt::format("{}: no folder after '='", text);
          if (!fs::is_directory(dir, ec))
            return fmt::format("{}: '{}' {}", text, dir, fs::exists(dir, ec) ? "is not a folder" : "does not exist");
        }
        return {};
      },
      "NAME=" + value_name, "NAME_VALUE");
}

}  // namespace

void add_urdf_options(CLI::App* cmd, std::vector<std::string>& packages, std::vector<std::string>& args) {
  cmd->add_option("--package", packages,
                  "Where a URDF's package://NAME/ points (repeatable); wins over the project's <package name=\"NAME\">")
      ->type_name("NAME=DIR")
      ->check(name_value("DIR", true));
  cmd->add_option("--arg", args,
                  "Text for a URDF's ${NAME} and $(arg NAME) (repeatable); wins over the project's <arg name=\"NAME\">")
      ->type_name("NAME=VALUE")
      ->check(name_value("VALUE", false));
}

UrdfOverrides urdf_overrides(const std::vector<std::string>& packages, const std::vector<std::string>& args) {
  UrdfOverrides out;
  for (const auto& p : packages) {
    const auto eq = p.find('=');
    out.packages[p.substr(0, eq)] = fs::absolute(p.substr(eq + 1)).lexically_normal().string();
  }
  for (const auto& a : args) {
    const auto eq = a.find('=');
    out.args[a.substr(0, eq)] = a.substr(eq + 1);
  }
  return out;
}

}  // namespace sear
