// `--package NAME=DIR` and `--arg NAME=VALUE`: the command line's additions to every URDF robot's
// mapping, for `sear run`, `sear view`, `sear check` and `sear test` alike.
#pragma once

#include <string>
#include <vector>

#include "scene/urdf_overrides.hpp"

namespace CLI {
class App;
}  // namespace CLI

namespace sear {

// Declares both options on `cmd`; a value without '=', with an empty name, or (--package) naming
// no folder is refused there, with the option's name.
void add_urdf_options(CLI::App* cmd, std::vector<std::string>& packages, std::vector<std::string>& args);

// The options' values as the loader takes them: each folder absolute (a run may work elsewhere),
// the last of a name given twice winning.
UrdfOverrides urdf_overrides(const std::vector<std::string>& packages, const std::vector<std::string>& args);

}  // namespace sear
