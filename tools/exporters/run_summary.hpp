// The end-of-run summary: sim and wall time, real-time factor, per-robot distance and
// collisions, as text for people and JSON for tools.
#pragma once

#include <cstdint>
#include <string>

#include <utility>
#include <vector>

#include "exporters/mcu_capture.hpp"
#include "runtime/lockstep.hpp"
#include "runtime/simulation.hpp"
#include "runtime/wiring_report.hpp"

namespace sear {

struct RunOutcome {
  std::string project_file;
  std::string project_name;
  std::uint64_t seed = 0;
  double wall_time_s = 0;
  StepWallTime step_wall;  // where the steps' wall time went (the capture is Lockstep's `alongside`)
  std::string status = "completed";  // or "interrupted", "mcu stopped", "physics failed"
  std::vector<McuStop> mcu_stops;    // firmware that crashed, exited, hung or was refused
  std::vector<McuHaltReport> mcu_halts;  // firmware that halted in `while (true);` and ran on
  std::vector<NeverSent> never_sent;  // bytes still queued when an MCU stopped or the run ended
  std::vector<std::string> truncated_files;  // outputs that reached their size limit
  // The run's ends on the host: a device and its pseudo-terminal, a CAN bus and its interface.
  struct HostPort {
    std::string name;  // "rover.main.gps" or "can_bus body"
    std::string path;  // "/dev/pts/3" or "vcan0"
    std::string link;  // a pty's stable link, "OUT/rover.main.gps.pty"; empty for CAN
    std::uint64_t dropped = 0;  // bytes or frames lost at this end (nobody reading, a full queue)
  };
  std::vector<HostPort> host_ports;
  // What the run was expected to show (a scenario's or the project's <expect>), once decided.
  struct Expectation {
    std::string name;
    std::string verdict;  // "passed" or "failed"
    double time_s;        // when it was decided
    std::string seen;     // for a failure: what was seen instead
  };
  std::vector<Expectation> expectations;
  // MCUs on the AVR engine: "robot.mcu" and the report its engine wrote (CPU load, ISRs, top
  // functions, stack; docs/avr-engine.md).
  std::vector<std::pair<std::string, std::string>> avr_reports;
  // Wiring that does not match what the firmware did (runtime/wiring_report.hpp), per MCU in order.
  std::vector<WiringNote> wiring;
  // What importing a URDF robot decided on its own (a snapped rpy, a derived inertia, a mesh
  // boxed), each at its file and line: printed before the run starts, kept here for tools.
  std::vector<std::pair<SourceRef, std::string>> import_warnings;
};

// "mcu rover.main crashed with signal 11 (...) at sim time 1.234 s; last HAL call: adc_read"
std::string describe(const McuStop& stop);

// "mcu rover.main halted at sim time 0.012509 s (an endless empty loop; its interrupts still run)"
std::string describe(const McuHaltReport& halt);

// "robot rover left the terrain at sim time 149.123 s at (20.01, -3.20, 0.41) m; it is stopped"
std::string describe(const RobotEvent& event);

std::string summary_text(const Simulation& sim, const RunOutcome& outcome);
std::string summary_json(const Simulation& sim, const RunOutcome& outcome);

}  // namespace sear
