#include "runtime/simulation.hpp"

#include <algorithm>
#include <cmath>

#include "physics/scenery.hpp"

namespace sear {

Simulation::Simulation(const ProjectDesc& project, std::uint64_t seed)
    : step_s_(project.world.step_s),
      physics_(std::make_unique<PhysicsWorld>(project.world, seed)),
      step_ns_(std::llround(project.world.step_s * 1e9)) {
  build_terrain(*physics_, project.world.terrain);
  // Placement is known only once the terrain exists: gather every problem, as the loader does.
  std::vector<std::string> problems = build_obstacles(*physics_, project.world, project.file);
  for (const auto& robot : project.robots) {
    try {
      vehicles_.push_back(std::make_unique<Vehicle>(*physics_, robot));
    } catch (const PlacementError& e) {
      problems.push_back(e.what());
      continue;
    }
    const auto p = vehicles_.back()->state().position_m;
    last_xy_.emplace_back(p.x(), p.y());
  }
  if (!problems.empty()) {
    std::string all;
    for (const auto& p : problems) all += (all.empty() ? "" : "\n") + p;
    throw PlacementError(all);
  }
  script_cursor_.assign(vehicles_.size(), 0);
  tallies_.assign(vehicles_.size(), RobotTally{});
}

void Simulation::run_scripts() {
  for (std::size_t r = 0; r < vehicles_.size(); ++r) {
    Vehicle& v = *vehicles_[r];
    const auto& script = v.desc().script;
    std::size_t& cursor = script_cursor_[r];
    // Commands are due when their time is reached: compared in integer nanoseconds so that a
    // command at t = 0.3 s applies at the 300th step whatever the rounding of 0.3.
    while (cursor < script.size() && std::llround(script[cursor].t_s * 1e9) <= time_ns_) {
      const ScriptCommand& cmd = script[cursor++];
      if (cmd.is_servo) v.command_servo(static_cast<std::size_t>(v.servo_index(cmd.actuator)), cmd.pulse_us);
      else v.command_motor(static_cast<std::size_t>(v.motor_index(cmd.actuator)), {cmd.duty, cmd.direction});
    }
  }
}

void Simulation::account_step() {
  for (std::size_t r = 0; r < vehicles_.size(); ++r) {
    const auto p = vehicles_[r]->state().position_m;
    const Eigen::Vector2d xy(p.x(), p.y());
    tallies_[r].distance_m += (xy - last_xy_[r]).norm();
    last_xy_[r] = xy;
  }
  const auto& now = physics_->touches();
  const auto& names = physics_->entity_names();
  for (const Touch& t : now) {
    if (std::find(touching_.begin(), touching_.end(), t) != touching_.end()) continue;
    for (std::size_t r = 0; r < vehicles_.size(); ++r) {
      if (vehicles_[r]->entity() != t.robot_entity) continue;
      ++tallies_[r].collisions;
      collisions_.push_back({time_ns_, names[static_cast<std::size_t>(t.robot_entity)],
                             names[static_cast<std::size_t>(t.other_entity)]});
    }
  }
  touching_ = now;
}

void Simulation::step() {
  run_scripts();
  for (auto& v : vehicles_) v->apply_actuators(step_s_);
  physics_->step();
  time_ns_ += step_ns_;
  account_step();
}

}  // namespace sear
