#include "runtime/lockstep.hpp"

#include <chrono>
#include <stdexcept>

namespace sear {

Lockstep::Lockstep(Simulation& sim, const ProjectDesc& project, const LockstepOptions& options, McuListener& listener)
    : sim_(sim), options_(options), listener_(listener) {
  for (std::size_t r = 0; r < project.robots.size(); ++r) {
    for (const auto& mcu : project.robots[r].mcus) {
      const std::string id = project.robots[r].name + "." + mcu.name;
      // Each MCU's noise is its own, and stays the same when other robots are added.
      const std::uint64_t seed = project.run.seed * 1000003u + bridges_.size();
      bridges_.push_back(std::make_unique<McuBridge>(mcu, project.world, id, bridges_.size(), sim.robot(r), seed,
                                                     options.out_dir + "/" + id + ".host.log", options.mcu));
      running_.push_back(true);
      halt_reported_.push_back(false);
      robot_of_.push_back(r);
    }
  }
  if (!project.can_buses.empty()) can_ = std::make_unique<CanNetwork>(project, bridges_, options.mcu.tap);
}

void Lockstep::attach_can_host(const std::string& bus, HostCanEnd* end) {
  if (!can_) throw std::invalid_argument("the project has no <can_bus> to bridge to the host");
  can_->attach_host(bus, end);
}

void Lockstep::retire_robot(std::size_t robot) {
  for (std::size_t i = 0; i < bridges_.size(); ++i) {
    if (robot_of_[i] != robot || !running_[i]) continue;
    running_[i] = false;
    bridges_[i]->shut_down(i, sim_.time_ns(), listener_);
  }
}

namespace {

// Adds the time since the last call to `*part`: one clock read a part.
class PartClock {
 public:
  void to(std::int64_t* part) {
    const auto now = std::chrono::steady_clock::now();
    *part += std::chrono::duration_cast<std::chrono::nanoseconds>(now - last_).count();
    last_ = now;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace

bool Lockstep::step(const std::function<void()>& alongside) {
  PartClock clock;
  ++wall_.steps;
  const std::int64_t t0 = sim_.time_ns();
  const std::int64_t t1 = t0 + sim_.step_ns();
  // Every firmware runs its quantum [t0, t1) in its own process, against sensors measured at t0,
  // while the world steps from t0 to t1 here with the actuator commands of the quantum before:
  // firmware and physics share the cores instead of taking turns. A motor thus acts one quantum
  // (1 ms) after the pin change that commands it, as an H-bridge and a gearbox lag anyway; the
  // order is fixed, so runs stay byte-identical. This took the default project from 77x to 87x.
  {
    // Nothing moves while the sensors measure: they share one list of what moves.
    const PhysicsWorld::HoldStill still(sim_.physics());
    if (can_) can_->begin_quantum(sim_, t0, t1);
    for (std::size_t i = 0; i < bridges_.size(); ++i)
      if (running_[i]) bridges_[i]->begin_quantum(sim_.physics(), t0, t1);
  }
  clock.to(&wall_.before_quantum_ns);
  if (alongside) alongside();
  clock.to(&wall_.alongside_ns);
  sim_.step();
  clock.to(&wall_.physics_ns);
  bool stopped = false;
  for (std::size_t i = 0; i < bridges_.size(); ++i) {
    if (!running_[i]) continue;
    const McuBridge::Outcome outcome = bridges_[i]->finish_quantum(i, listener_);
    if (!halt_reported_[i] && bridges_[i]->halt()) {
      halt_reported_[i] = true;
      halts_.push_back({bridges_[i]->id(), *bridges_[i]->halt()});
    }
    if (outcome == McuBridge::Outcome::Running) continue;
    // The others still hold their turn; they are stopped with the run, their quantum unfinished.
    if (outcome == McuBridge::Outcome::Interrupted) return false;
    running_[i] = false;
    stops_.push_back({bridges_[i]->id(), *bridges_[i]->failure()});
    stopped = true;
  }
  if (can_) can_->finish_quantum(t0, t1);
  if (options_.mcu.tap) options_.mcu.tap->on_step(sim_);
  clock.to(&wall_.after_quantum_ns);
  if (stopped && !options_.keep_going) return false;
  return true;
}

}  // namespace sear
