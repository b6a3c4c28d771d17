// What the command line adds to every URDF robot's mapping (`--package NAME=DIR`,
// `--arg NAME=VALUE`): a name given there wins over the project's <package> or <arg> of that name.
#pragma once

#include <map>
#include <string>

namespace sear {

struct UrdfOverrides {
  std::map<std::string, std::string> packages;  // package:// name -> folder (absolute)
  std::map<std::string, std::string> args;      // ${NAME} and $(arg NAME) -> text
};

}  // namespace sear
