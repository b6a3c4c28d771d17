#include "test_world.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "scene/project_loader.hpp"

namespace sear::test {

ProjectDesc project_from_xml(const std::string& xml) {
  Diagnostics diagnostics;
  auto project = load_project_text(xml, std::string(SEAR_ASSET_DIR) + "/projects/inline_test.xml", diagnostics);
  if (!project) throw std::runtime_error("test project does not load:\n" + diagnostics.joined() + xml);
  return *project;
}

std::string project_xml(const std::string& world_attributes, const std::string& world_children,
                        const std::string& robots) {
  return fmt::format(R"(<project name="test">
  <world {}>
    <material name="rubber" friction="1.0"/>
    <material name="plastic" friction="0.4"/>
    {}
  </world>
  {}
</project>)",
                     world_attributes, world_children, robots);
}

void run_for(Simulation& sim, double seconds, const std::function<void()>& each_step) {
  const std::int64_t end = sim.time_ns() + static_cast<std::int64_t>(seconds * 1e9 + 0.5);
  while (sim.time_ns() < end) {
    sim.step();
    if (each_step) each_step();
  }
}

void drive(Simulation& sim, const std::string& motor, double duty, MotorDirection direction) {
  Vehicle& v = sim.robot(0);
  const int index = v.motor_index(motor);
  if (index < 0) throw std::invalid_argument("robot '" + v.desc().name + "' has no motor '" + motor + "'");
  v.command_motor(static_cast<std::size_t>(index), {duty, direction});
}

}  // namespace sear::test
