// The end-of-run summary: sim and wall time, real-time factor, per-robot distance and
// collisions, as text for people and JSON for tools.
#pragma once

#include <cstdint>
#include <string>

#include <vector>

#include "runtime/lockstep.hpp"
#include "runtime/simulation.hpp"

namespace sear {

struct RunOutcome {
  std::string project_file;
  std::string project_name;
  std::uint64_t seed = 0;
  double wall_time_s = 0;
  std::string status = "completed";  // or "interrupted", "mcu stopped", "physics failed"
  std::vector<McuStop> mcu_stops;    // firmware that crashed, exited, hung or was refused
  std::vector<std::string> truncated_files;  // outputs that reached their size limit
};

// "mcu rover.main crashed with signal 11 (...) at sim time 1.234 s; last HAL call: adc_read"
std::string describe(const McuStop& stop);

// "robot rover left the terrain at sim time 149.123 s at (20.01, -3.20, 0.41) m; it is stopped"
std::string describe(const RobotEvent& event);

std::string summary_text(const Simulation& sim, const RunOutcome& outcome);
std::string summary_json(const Simulation& sim, const RunOutcome& outcome);

}  // namespace sear
