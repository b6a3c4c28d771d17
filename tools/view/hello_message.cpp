#include "view/hello_message.hpp"

#include <nlohmann/json.hpp>

#include "scene/description.hpp"

namespace sear {

std::string view_hello_json(const ProjectDesc& project, const std::string& mode) {
  const nlohmann::json hello = {{"type", "hello"},
                                {"version", 1},
                                {"mode", mode},
                                {"project", project.name},
                                {"step_s", project.world.step_s},
                                {"duration_s", project.run.duration_s}};
  return hello.dump();
}

}  // namespace sear
