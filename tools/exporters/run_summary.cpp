#include "exporters/run_summary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>

#include <nlohmann/json.hpp>

#include "exporters/printable_text.hpp"

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

std::string describe(const McuHaltReport& h) {
  return fmt::format("mcu {} halted at sim time {:.6f} s ({})", h.mcu, static_cast<double>(h.halt.time_ns) * 1e-9,
                     describe(h.halt));
}

std::string describe(const RobotEvent& e) {
  return fmt::format("robot {} {} at sim time {:.3f} s at ({:.2f}, {:.2f}, {:.2f}) m{}", e.robot_name, to_string(e.kind),
                     static_cast<double>(e.time_ns) * 1e-9, e.position_m.x(), e.position_m.y(), e.position_m.z(),
                     e.stops_robot ? "; it left the world and is stopped" : "");
}

std::string summary_text(const Simulation& sim, const RunOutcome& o) {
  std::string out = fmt::format("SEAR run of '{}' ({}), seed {}: {}\n", o.project_name, o.project_file, o.seed, o.status);
  out += fmt::format("  sim time {:.3f} s, wall time {:.3f} s, real-time factor {:.1f}x\n", sim.time_s(), o.wall_time_s,
                     real_time_factor(sim, o));
  for (std::size_t r = 0; r < sim.robot_count(); ++r) {
    const auto& v = sim.robot(r);
    const auto p = sim.robot_state(r).position_m;
    out += fmt::format("  robot {}: distance {:.2f} m, collisions {}, final position ({:.2f}, {:.2f}, {:.2f}) m{}\n",
                       v.desc().name, sim.tally(r).distance_m, sim.tally(r).collisions, p.x(), p.y(), p.z(),
                       sim.robot_stopped(r) ? ", stopped" : "");
  }
  for (const auto& e : sim.robot_events()) out += fmt::format("  {}\n", describe(e));
  if (sim.physics_failure()) out += fmt::format("  {}\n", *sim.physics_failure());
  for (const auto& c : sim.collisions())
    out += fmt::format("  collision at {:.3f} s: {} hit {}\n", static_cast<double>(c.time_ns) * 1e-9, c.robot, c.other);
  for (const auto& stop : o.mcu_stops) out += fmt::format("  {}\n", describe(stop));
  for (const auto& halt : o.mcu_halts) out += fmt::format("  {}\n", describe(halt));
  for (const auto& n : o.never_sent)
    out += fmt::format("  mcu {}: {} bytes queued on uart{} never sent ({})\n", n.mcu, n.bytes.size(), n.port,
                       n.mcu_stopped ? "it stopped" : "the run ended");
  for (const auto& e : o.expectations)
    if (e.verdict == "failed") out += fmt::format("  expectation failed at {:.3f} s: {}: {}\n", e.time_s, e.name, e.seen);
  const auto count = [&](const char* verdict) {
    return std::count_if(o.expectations.begin(), o.expectations.end(),
                         [&](const auto& e) { return e.verdict == verdict; });
  };
  // Undecided only when the run was interrupted before their deadlines: not failures.
  if (!o.expectations.empty())
    out += fmt::format("  expectations: {} of {} passed{}\n", count("passed"), o.expectations.size(),
                       count("undecided") ? fmt::format(", {} undecided (the run was interrupted before their deadlines)",
                                                        count("undecided"))
                                          : "");
  for (const auto& n : o.wiring)
    out += fmt::format("  {}: {}\n", n.kind == WiringNote::Kind::Unused ? "wiring" : "pin note", n.text);
  for (const auto& [at, text] : o.import_warnings)
    out += fmt::format("  import warning: {}:{}: {}\n", at.file, at.line, text);
  for (const auto& port : o.host_ports)
    out += fmt::format("  {} on the host: {}{}{}\n", port.name, port.path, port.link.empty() ? "" : " (link " + port.link + ")",
                       port.dropped ? fmt::format(", {} dropped", port.dropped) : "");
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
  const ConstraintSolver::Counts& solver = sim.physics().solver_counts();
  j["solver_steps"] = {{"direct", solver.direct}, {"iterative", solver.iterative}, {"retaken", solver.retaken}};
  // Means a step, in microseconds; wall-clock figures like the two above.
  const auto per_step_us = [&](std::int64_t ns) {
    return o.step_wall.steps ? static_cast<double>(ns) * 1e-3 / static_cast<double>(o.step_wall.steps) : 0.0;
  };
  j["step_wall_us"] = {{"before_quantum", per_step_us(o.step_wall.before_quantum_ns)},
                       {"capture", per_step_us(o.step_wall.alongside_ns)},
                       {"physics", per_step_us(o.step_wall.physics_ns)},
                       {"after_quantum", per_step_us(o.step_wall.after_quantum_ns)}};
  j["robots"] = nlohmann::ordered_json::array();
  for (std::size_t r = 0; r < sim.robot_count(); ++r) {
    const auto& v = sim.robot(r);
    const auto s = sim.robot_state(r);
    j["robots"].push_back({{"name", v.desc().name},
                           {"distance_m", sim.tally(r).distance_m},
                           {"collisions", sim.tally(r).collisions},
                           {"final_position_m", {s.position_m.x(), s.position_m.y(), s.position_m.z()}},
                           {"final_yaw_rad", s.roll_pitch_yaw.z()},
                           {"status", sim.robot_stopped(r) ? "stopped" : "running"}});
  }
  j["robot_events"] = nlohmann::ordered_json::array();
  for (const auto& e : sim.robot_events())
    j["robot_events"].push_back({{"time_s", static_cast<double>(e.time_ns) * 1e-9},
                                 {"robot", e.robot_name},
                                 {"kind", to_string(e.kind)},
                                 {"position_m", {e.position_m.x(), e.position_m.y(), e.position_m.z()}},
                                 {"stopped", e.stops_robot}});
  if (sim.physics_failure()) j["physics_failure"] = *sim.physics_failure();
  else j["physics_failure"] = nullptr;
  j["collision_events"] = nlohmann::ordered_json::array();
  for (const auto& c : sim.collisions())
    j["collision_events"].push_back(
        {{"time_s", static_cast<double>(c.time_ns) * 1e-9}, {"robot", c.robot}, {"other", c.other}});
  j["mcu_stops"] = nlohmann::ordered_json::array();
  for (const auto& stop : o.mcu_stops) {
    // Its last words: per port, what it had queued that never left (bytes as \xNN where not text).
    nlohmann::ordered_json unsent = nlohmann::ordered_json::object();
    for (const auto& n : o.never_sent)
      if (n.mcu == stop.mcu && n.mcu_stopped) unsent[fmt::format("uart{}", n.port)] = printable(n.bytes, true);
    j["mcu_stops"].push_back({{"mcu", stop.mcu},
                              {"kind", kind_name(stop.failure.kind)},
                              {"code", stop.failure.code},
                              {"detail", stop.failure.detail},
                              {"sim_time_s", static_cast<double>(stop.failure.time_ns) * 1e-9},
                              {"last_hal_call", stop.failure.last_call},
                              {"never_sent", unsent}});
  }
  j["mcu_halts"] = nlohmann::ordered_json::array();
  for (const auto& h : o.mcu_halts)
    j["mcu_halts"].push_back({{"mcu", h.mcu},
                              {"sim_time_s", static_cast<double>(h.halt.time_ns) * 1e-9},
                              {"interrupts", h.halt.interrupts_off ? "off" : "on"}});
  j["never_sent"] = nlohmann::ordered_json::array();
  for (const auto& n : o.never_sent)
    j["never_sent"].push_back({{"mcu", n.mcu},
                               {"port", n.port},
                               {"time_s", static_cast<double>(n.time_ns) * 1e-9},
                               {"why", n.mcu_stopped ? "mcu stopped" : "run ended"},
                               {"bytes", n.bytes.size()},
                               {"text", printable(n.bytes, true)}});
  j["truncated_files"] = o.truncated_files;
  j["expectations"] = nlohmann::ordered_json::array();
  for (const auto& e : o.expectations)
    j["expectations"].push_back({{"name", e.name}, {"verdict", e.verdict}, {"time_s", e.time_s}, {"seen", e.seen}});
  j["avr_engines"] = nlohmann::ordered_json::object();
  for (const auto& [mcu, file] : o.avr_reports) {
    std::ifstream in(file);
    // An engine stopped before its first report leaves none: null rather than a guess.
    j["avr_engines"][mcu] = nlohmann::ordered_json::parse(in, nullptr, false);
    if (j["avr_engines"][mcu].is_discarded()) j["avr_engines"][mcu] = nullptr;
  }
  j["wiring"] = nlohmann::ordered_json::array();
  for (const auto& n : o.wiring)
    j["wiring"].push_back({{"mcu", n.mcu}, {"kind", kind_name(n.kind)}, {"device", n.device}, {"pin", n.pin}, {"text", n.text}});
  j["import_warnings"] = nlohmann::ordered_json::array();
  for (const auto& [at, text] : o.import_warnings)
    j["import_warnings"].push_back({{"file", at.file}, {"line", at.line}, {"text", text}});
  j["host_ports"] = nlohmann::ordered_json::array();
  for (const auto& port : o.host_ports) j["host_ports"].push_back({{"name", port.name}, {"path", port.path}, {"link", port.link}, {"dropped", port.dropped}});
  // Names are checked UTF-8 at load, but paths from the command line are the user's bytes: any
  // that are not UTF-8 are written with U+FFFD rather than losing the whole summary.
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace sear
