// The lockstep scheduler: every quantum, each MCU's firmware runs up to the quantum's end against
// sensors measured at its start, while the physics steps with the actuator commands the quantum
// before left; this quantum's commands drive the next step.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "runtime/can_network.hpp"
#include "runtime/mcu_bridge.hpp"
#include "runtime/run_tap.hpp"
#include "runtime/simulation.hpp"

namespace sear {

struct LockstepOptions {
  std::string out_dir;         // each MCU's host log (its stdout and stderr) goes here
  McuRunOptions mcu;           // its tap is told of every MCU, CAN bus and step
  bool keep_going = false;     // a stopped MCU ends the run, unless this is set
};

struct McuStop {
  std::string mcu;  // "robot.mcu"
  McuFailure failure;
};

struct McuHaltReport {
  std::string mcu;  // "robot.mcu"
  McuHalt halt;
};

// Where the steps' wall time went, summed over the steps, in host nanoseconds: what a step waits
// for on the simulator's side, so that a change can be judged by its part of a step within one
// run, whatever the host's speed at the moment.
struct StepWallTime {
  std::int64_t steps = 0;
  std::int64_t before_quantum_ns = 0;  // the sensors' truth, the serial lines, the turns given
  std::int64_t alongside_ns = 0;       // `alongside` (the capture), while the firmware runs
  std::int64_t physics_ns = 0;         // the world's step, while the firmware runs
  std::int64_t after_quantum_ns = 0;   // waiting for each firmware's quantum to end, its events
};

class Lockstep {
 public:
  // Starts one process per MCU of every robot; each McuDesc must name its built executable.
  Lockstep(Simulation& sim, const ProjectDesc& project, const LockstepOptions& options, McuListener& listener);

  // One quantum. False when an MCU stopped and the run should end (without keep_going), or when
  // the run was asked to stop (stop_requested()) while a firmware had the turn. `alongside`, if
  // given, runs once every firmware has its turn and before the world steps: work that needs
  // neither (the files of the step before) then costs the run no time while the firmware runs.
  bool step(const std::function<void()>& alongside = {});
  // The robot left the world: its MCUs are shut down, their output ending now. Not an MCU stop:
  // the robot's event says why.
  void retire_robot(std::size_t robot);

  std::size_t mcu_count() const { return bridges_.size(); }
  const McuBridge& mcu(std::size_t i) const { return *bridges_[i]; }
  const std::vector<McuStop>& stops() const { return stops_; }
  // MCUs that halted in an endless empty loop, in the order the run saw it; they run on.
  const std::vector<McuHaltReport>& halts() const { return halts_; }
  const StepWallTime& wall_time() const { return wall_; }
  // Bridges a <can_bus> to the host; see CanNetwork::attach_host.
  void attach_can_host(const std::string& bus, HostCanEnd* end);

 private:
  Simulation& sim_;
  LockstepOptions options_;
  McuListener& listener_;
  std::vector<std::unique_ptr<McuBridge>> bridges_;
  std::vector<bool> running_;
  std::vector<std::size_t> robot_of_;  // per bridge, the index of its robot
  std::vector<McuStop> stops_;
  std::vector<McuHaltReport> halts_;
  std::vector<bool> halt_reported_;
  std::unique_ptr<CanNetwork> can_;  // null when the project has no <can_bus>
  StepWallTime wall_;
};

}  // namespace sear
