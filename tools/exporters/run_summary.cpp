#include "exporters/run_summary.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

namespace sear {

namespace {
double real_time_factor(const Simulation& sim, const RunOutcome& o) {
  return o.wall_time_s > 0 ? sim.time_s() / o.wall_time_s : 0.0;
}
}  // namespace

std::string describe(const McuStop& stop) {
  return fmt::format("mcu {} {} at sim time {:.6f} s; last HAL call: {}", stop.mcu, describe(stop.failure),
                     static_cast<double>(stop.failure.time_ns) * 1e-9, stop.failure.last_call);
}

std::string summary_text(const Simulation& sim, const RunOutcome& o) {
  std::string out = fmt::format("SEAR run of '{}' ({}), seed {}: {}\n", o.project_name, o.project_file, o.seed, o.status);
  out += fmt::format("  sim time {:.3f} s, wall time {:.3f} s, real-time factor {:.1f}x\n", sim.time_s(), o.wall_time_s,
                     real_time_factor(sim, o));
  for (std::size_t r = 0; r < sim.robot_count(); ++r) {
    const auto& v = sim.robot(r);
    const auto p = v.state().position_m;
    out += fmt::format("  robot {}: distance {:.2f} m, collisions {}, final position ({:.2f}, {:.2f}, {:.2f}) m\n",
                       v.desc().name, sim.tally(r).distance_m, sim.tally(r).collisions, p.x(), p.y(), p.z());
  }
  for (const auto& c : sim.collisions())
    out += fmt::format("  collision at {:.3f} s: {} hit {}\n", static_cast<double>(c.time_ns) * 1e-9, c.robot, c.other);
  for (const auto& stop : o.mcu_stops) out += fmt::format("  {}\n", describe(stop));
  return out;
}

std::string summary_json(const Simulation& sim, const RunOutcome& o) {
  nlohmann::ordered_json j;
  j["project"] = o.project_name;
  j["project_file"] = o.project_file;
  j["seed"] = o.seed;
  j["status"] = o.status;
  j["sim_time_s"] = sim.time_s();
  j["wall_time_s"] = o.wall_time_s;
  j["real_time_factor"] = real_time_factor(sim, o);
  j["steps"] = sim.time_ns() / sim.step_ns();
  j["robots"] = nlohmann::ordered_json::array();
  for (std::size_t r = 0; r < sim.robot_count(); ++r) {
    const auto& v = sim.robot(r);
    const auto s = v.state();
    j["robots"].push_back({{"name", v.desc().name},
                           {"distance_m", sim.tally(r).distance_m},
                           {"collisions", sim.tally(r).collisions},
                           {"final_position_m", {s.position_m.x(), s.position_m.y(), s.position_m.z()}},
                           {"final_yaw_rad", s.roll_pitch_yaw.z()}});
  }
  j["collision_events"] = nlohmann::ordered_json::array();
  for (const auto& c : sim.collisions())
    j["collision_events"].push_back(
        {{"time_s", static_cast<double>(c.time_ns) * 1e-9}, {"robot", c.robot}, {"other", c.other}});
  j["mcu_stops"] = nlohmann::ordered_json::array();
  static const char* const kinds[] = {"exited", "crashed", "hung", "refused"};
  for (const auto& stop : o.mcu_stops)
    j["mcu_stops"].push_back({{"mcu", stop.mcu},
                              {"kind", kinds[static_cast<int>(stop.failure.kind)]},
                              {"code", stop.failure.code},
                              {"detail", stop.failure.detail},
                              {"sim_time_s", static_cast<double>(stop.failure.time_ns) * 1e-9},
                              {"last_hal_call", stop.failure.last_call}});
  return j.dump(2) + "\n";
}

}  // namespace sear
