#include <filesystem>

#include "sear/commands.hpp"

namespace sear {

std::string resolve_project_path(const std::string& argument) {
  if (argument.empty()) return SEAR_DEFAULT_PROJECT;
  if (auto sketch = sketch_default_project(argument)) return *sketch;
  if (std::filesystem::is_directory(argument)) return (std::filesystem::path(argument) / "project.xml").string();
  return argument;
}

}  // namespace sear
