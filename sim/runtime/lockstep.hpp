// The lockstep scheduler: every quantum, each MCU's firmware runs up to the quantum's end against
// sensors measured at its start, then the physics steps with the actuator commands they left.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "runtime/mcu_bridge.hpp"
#include "runtime/simulation.hpp"

namespace sear {

struct LockstepOptions {
  std::string out_dir;         // each MCU's host log (its stdout and stderr) goes here
  double hang_timeout_s = 5;   // host time without progress before a firmware counts as hung
  bool keep_going = false;     // a stopped MCU ends the run, unless this is set
};

struct McuStop {
  std::string mcu;  // "robot.mcu"
  McuFailure failure;
};

class Lockstep {
 public:
  // Starts one process per MCU of every robot; each McuDesc must name its built executable.
  Lockstep(Simulation& sim, const ProjectDesc& project, const LockstepOptions& options, McuListener& listener);

  // One quantum. False when an MCU stopped and the run should end (without keep_going).
  bool step();

  std::size_t mcu_count() const { return bridges_.size(); }
  const McuBridge& mcu(std::size_t i) const { return *bridges_[i]; }
  const std::vector<McuStop>& stops() const { return stops_; }

 private:
  Simulation& sim_;
  LockstepOptions options_;
  McuListener& listener_;
  std::vector<std::unique_ptr<McuBridge>> bridges_;
  std::vector<bool> running_;
  std::vector<McuStop> stops_;
};

}  // namespace sear
