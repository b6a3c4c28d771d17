// The end-of-run summary: sim and wall time, real-time factor, per-robot distance and
// collisions, as text for people and JSON for tools.
#pragma once

#include <cstdint>
#include <string>

#include "runtime/simulation.hpp"

namespace sear {

struct RunOutcome {
  std::string project_file;
  std::string project_name;
  std::uint64_t seed = 0;
  double wall_time_s = 0;
  std::string status = "completed";  // or "interrupted"
};

std::string summary_text(const Simulation& sim, const RunOutcome& outcome);
std::string summary_json(const Simulation& sim, const RunOutcome& outcome);

}  // namespace sear
