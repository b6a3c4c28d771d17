#include "runtime/lockstep.hpp"

namespace sear {

Lockstep::Lockstep(Simulation& sim, const ProjectDesc& project, const LockstepOptions& options, McuListener& listener)
    : sim_(sim), options_(options), listener_(listener) {
  for (std::size_t r = 0; r < project.robots.size(); ++r) {
    for (const auto& mcu : project.robots[r].mcus) {
      const std::string id = project.robots[r].name + "." + mcu.name;
      // Each MCU's noise is its own, and stays the same when other robots are added.
      const std::uint64_t seed = project.run.seed * 1000003u + bridges_.size();
      bridges_.push_back(std::make_unique<McuBridge>(mcu, id, sim.robot(r), seed,
                                                     options.out_dir + "/" + id + ".host.log", options.hang_timeout_s));
      running_.push_back(true);
    }
  }
}

bool Lockstep::step() {
  const std::int64_t t0 = sim_.time_ns();
  const std::int64_t t1 = t0 + sim_.step_ns();
  // All firmware runs its quantum at once, each in its own process, then the world moves.
  for (std::size_t i = 0; i < bridges_.size(); ++i)
    if (running_[i]) bridges_[i]->begin_quantum(sim_.physics(), t0, t1);
  bool stopped = false;
  for (std::size_t i = 0; i < bridges_.size(); ++i) {
    if (!running_[i] || bridges_[i]->finish_quantum(i, listener_)) continue;
    running_[i] = false;
    stops_.push_back({bridges_[i]->id(), *bridges_[i]->failure()});
    stopped = true;
  }
  if (stopped && !options_.keep_going) return false;
  sim_.step();
  return true;
}

}  // namespace sear
