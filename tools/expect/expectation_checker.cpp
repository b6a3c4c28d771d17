#include "expect/expectation_checker.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "scene/device_kind.hpp"

namespace sear {
namespace {

// std::regex (libstdc++) matches by recursion, a few frames per character: "(a|b)*c" searched in
// a line of 'a's overflowed the main thread's 8 MiB stack between 8 and 12 KiB here. Lines are
// matched on their first 4 KiB, half that, and far longer than any line a firmware prints on purpose.
constexpr std::size_t kMaxLineBytes = 4096;

std::string quoted(const std::string& line) { return "'" + line + "'"; }

}  // namespace

ExpectationChecker::ExpectationChecker(const Scenario& scenario, const ProjectDesc& project) : scenario_(scenario) {
  std::vector<std::string> robots;
  for (const auto& robot : project.robots) {
    robots.push_back(robot.name);
    for (const auto& desc : robot.mcus) {
      Mcu m;
      m.id = robot.name + "." + desc.name;
      m.console_port = desc.console_uart;
      for (const auto& d : desc.devices) {
        int port = -1;
        for (std::size_t w = 0; w < d.wires.size(); ++w)
          if (d.kind->wires[w].kind == WireKind::UartPort && d.wires[w] >= 0 && d.wires[w] < 4) port = d.wires[w];
        m.device_port.push_back(port);
        if (port >= 0) m.port_has_device[static_cast<std::size_t>(port)] = true;
      }
      mcus_.push_back(std::move(m));
    }
  }
  by_mcu_.resize(mcus_.size());
  for (const auto& e : scenario.expectations) {
    ExpectationResult r;
    r.expectation = &e;
    results_.push_back(r);
    Live l;
    for (std::size_t m = 0; m < mcus_.size(); ++m)
      if (mcus_[m].id == e.mcu) l.mcu = m;
    for (std::size_t i = 0; i < robots.size(); ++i)
      if (robots[i] == e.robot) l.robot = i;
    if (l.mcu != SIZE_MAX) by_mcu_[l.mcu].push_back(results_.size() - 1);
    live_.push_back(l);
  }
  pending_ = results_.size();
}

std::int64_t ExpectationChecker::deadline(const Expectation& e) const {
  if (e.before_ns) return *e.before_ns;
  return scenario_.timeout_ns.value_or(INT64_MAX);
}

void ExpectationChecker::pass(std::size_t i, std::int64_t time_ns) {
  if (results_[i].verdict != Verdict::Pending) return;
  results_[i].verdict = Verdict::Passed;
  results_[i].time_ns = time_ns;
  --pending_;
}

void ExpectationChecker::fail(std::size_t i, std::int64_t time_ns, std::string seen) {
  if (results_[i].verdict != Verdict::Pending) return;
  results_[i].verdict = Verdict::Failed;
  results_[i].time_ns = time_ns;
  results_[i].seen = std::move(seen);
  --pending_;
}

bool ExpectationChecker::decided() const { return pending_ == 0; }

bool ExpectationChecker::passed() const {
  return decided() && std::none_of(results_.begin(), results_.end(),
                                   [](const ExpectationResult& r) { return r.verdict == Verdict::Failed; });
}

// ---- events ----

void ExpectationChecker::on_mcu_event(std::size_t mcu, const sear_event& e) {
  Mcu& m = mcus_[mcu];
  if (by_mcu_[mcu].empty() || e.time_ns > m.stop_ns) return;
  switch (e.kind) {
    case SEAR_EVENT_UART_RX:
      // A device's bytes are taken from its wire (on_wire_bytes), whether or not the firmware
      // has started its receiver; RX events then only repeat them.
      if (e.index >= 4 || m.port_has_device[e.index]) return;
      break;
    case SEAR_EVENT_UART_TX:
      if (e.index >= 4) return;
      break;
    case SEAR_EVENT_PIN:
    case SEAR_EVENT_PIN_MODE:
    case SEAR_EVENT_PWM:
      if (e.index >= m.pins.size()) return;
      break;
    default:
      return;
  }
  m.pending.push_back({e.time_ns, e.kind, e.index, e.value});
}

void ExpectationChecker::on_wire_bytes(std::size_t mcu, std::size_t device, bool from_device,
                                       const serial_byte* bytes, std::size_t count) {
  Mcu& m = mcus_[mcu];
  // Bytes towards the device are the MCU's TX events already.
  if (!from_device || by_mcu_[mcu].empty() || device >= m.device_port.size() || m.device_port[device] < 0) return;
  const auto port = static_cast<std::uint8_t>(m.device_port[device]);
  for (std::size_t i = 0; i < count; ++i)
    if (bytes[i].end_ns <= m.stop_ns) m.pending.push_back({bytes[i].end_ns, SEAR_EVENT_UART_RX, port, bytes[i].value});
}

// Takes MCU m's events up to `until_ns` in time order, each group of equal times at once: an
// output's mode and level change together at one instant, and no expectation sees between them.
void ExpectationChecker::take(std::size_t m, std::int64_t until_ns, bool inclusive) {
  Mcu& s = mcus_[m];
  if (s.pending.empty()) return;
  // Reported in time order per kind, but a byte sent is stamped ahead of the pin changes after it.
  std::stable_sort(s.pending.begin(), s.pending.end(),
                   [](const Event& a, const Event& b) { return a.time_ns < b.time_ns; });
  const auto due = [&](std::int64_t t) { return inclusive ? t <= until_ns : t < until_ns; };
  std::size_t n = 0;
  while (n < s.pending.size() && due(s.pending[n].time_ns)) {
    const std::int64_t t = s.pending[n].time_ns;
    if (t > s.stop_ns) {
      ++n;
      continue;
    }
    settle(m, t - 1);
    for (; n < s.pending.size() && s.pending[n].time_ns == t; ++n) apply(m, s.pending[n]);
    settle_pins(m, t);
  }
  s.pending.erase(s.pending.begin(), s.pending.begin() + static_cast<std::ptrdiff_t>(n));
}

void ExpectationChecker::apply(std::size_t m, const Event& e) {
  Mcu& s = mcus_[m];
  switch (e.kind) {
    case SEAR_EVENT_PIN_MODE:
      s.pins[e.index].output = e.value == 1;  // OUTPUT; its level follows as a PIN event
      s.pins[e.index].pwm = 0;
      return;
    case SEAR_EVENT_PIN:
      s.pins[e.index].level = e.value ? 1 : 0;
      s.pins[e.index].pwm = 0;
      return;
    case SEAR_EVENT_PWM:
      s.pins[e.index].output = true;
      s.pins[e.index].pwm = static_cast<int>(e.value);
      return;
    default:
      break;
  }
  const bool tx = e.kind == SEAR_EVENT_UART_TX;
  const auto byte = static_cast<char>(e.value);
  for (std::size_t i : by_mcu_[m]) {
    const auto* u = std::get_if<UartExpect>(&scenario_.expectations[i].what);
    if (!u || u->tx != tx || u->port != e.index || results_[i].verdict != Verdict::Pending) continue;
    Live& l = live_[i];
    ++l.counted;
    if (u->at_least) {
      if (l.counted >= u->at_least) pass(i, e.time_ns);
      continue;
    }
    l.window.push_back(byte);
    if (l.window.size() > u->pattern.size()) l.window.erase(l.window.begin());
    if (l.window == u->pattern) pass(i, e.time_ns);
  }
  // The console as console.log holds it: a line ends at '\n', stamped with it; '\r' is dropped.
  if (tx && e.index == s.console_port) {
    s.line_time = e.time_ns;
    if (byte == '\n') end_line(m);
    else if (byte != '\r' && s.line.size() < kMaxLineBytes) s.line.push_back(byte);
  }
}

void ExpectationChecker::end_line(std::size_t m) {
  Mcu& s = mcus_[m];
  ++s.lines;
  for (std::size_t i : by_mcu_[m]) {
    const auto* c = std::get_if<ConsoleExpect>(&scenario_.expectations[i].what);
    if (!c || results_[i].verdict != Verdict::Pending || !std::regex_search(s.line, *c->regex)) continue;
    if (c->never) fail(i, s.line_time, fmt::format("line {} at {}", quoted(s.line), seconds_text(s.line_time)));
    else pass(i, s.line_time);
  }
  s.last_line = std::move(s.line);
  s.last_line_time = s.line_time;
  s.line.clear();
}

std::string ExpectationChecker::pin_text(const PinState& p) const {
  if (!p.output) return "not driven (an input)";
  if (p.pwm) return fmt::format("a PWM waveform (duty {}/255)", p.pwm);
  return std::to_string(p.level);
}

// After the events at time_ns: a pin that must hold its level over an interval under way.
void ExpectationChecker::settle_pins(std::size_t m, std::int64_t time_ns) {
  for (std::size_t i : by_mcu_[m]) {
    const auto* p = std::get_if<PinExpect>(&scenario_.expectations[i].what);
    if (!p || results_[i].verdict != Verdict::Pending || !live_[i].pin_started || time_ns > p->to_ns) continue;
    const PinState& s = mcus_[m].pins[static_cast<std::size_t>(p->pin)];
    if (!s.output || s.pwm || s.level != p->level)
      fail(i, time_ns, fmt::format("pin {} was {} at {}", p->pin, pin_text(s), seconds_text(time_ns)));
  }
}

// What a pending MCU expectation has seen by `at_ns`, for its failure.
std::string ExpectationChecker::seen_by(std::size_t i, std::int64_t at_ns) const {
  const Mcu& s = mcus_[live_[i].mcu];
  const Expectation& e = scenario_.expectations[i];
  if (std::holds_alternative<ConsoleExpect>(e.what)) {
    if (!s.lines) return fmt::format("no console line by {}", seconds_text(at_ns));
    return fmt::format("no line matched among {} by {}; the last: {} at {}", s.lines, seconds_text(at_ns),
                       quoted(s.last_line), seconds_text(s.last_line_time));
  }
  if (const auto* u = std::get_if<UartExpect>(&e.what)) {
    if (u->at_least)
      return fmt::format("{} byte{} by {}", live_[i].counted, live_[i].counted == 1 ? "" : "s", seconds_text(at_ns));
    return fmt::format("not among the {} bytes by {}", live_[i].counted, seconds_text(at_ns));
  }
  if (const auto* p = std::get_if<PinExpect>(&e.what))
    return fmt::format("pin {} was {} at {}", p->pin, pin_text(s.pins[static_cast<std::size_t>(p->pin)]),
                       seconds_text(at_ns));
  return "";
}

// Decides MCU m's expectations whose instants are all at or before `known_ns`, every event up to
// it being taken.
void ExpectationChecker::settle(std::size_t m, std::int64_t known_ns) {
  for (std::size_t i : by_mcu_[m]) {
    if (results_[i].verdict != Verdict::Pending) continue;
    const Expectation& e = scenario_.expectations[i];
    const std::int64_t d = deadline(e);
    if (const auto* p = std::get_if<PinExpect>(&e.what)) {
      Live& l = live_[i];
      if (!l.pin_started && p->from_ns <= known_ns) {
        const PinState& s = mcus_[m].pins[static_cast<std::size_t>(p->pin)];
        if (!s.output || s.pwm || s.level != p->level) {
          fail(i, p->from_ns, seen_by(i, p->from_ns));
          continue;
        }
        l.pin_started = true;
      }
      if (l.pin_started && p->to_ns <= known_ns) pass(i, p->to_ns);
      continue;
    }
    if (d > known_ns) continue;
    const auto* c = std::get_if<ConsoleExpect>(&e.what);
    if ((c && c->never) || std::holds_alternative<RunningExpect>(e.what)) pass(i, d);
    else fail(i, d, seen_by(i, d));
  }
}

// ---- the world ----

void ExpectationChecker::on_step(const Simulation& sim) {
  WorldMoment w;
  w.time_ns = sim.time_ns();
  for (std::size_t r = 0; r < sim.robot_count(); ++r) w.robot_xy_m.push_back(sim.robot_state(r).position_m.head<2>());
  const auto& all = sim.collisions();
  w.new_collisions.assign(all.begin() + static_cast<std::ptrdiff_t>(std::min(collisions_seen_, all.size())), all.end());
  collisions_seen_ = all.size();
  advance(w);
}

void ExpectationChecker::advance(const WorldMoment& w) {
  // Events before the previous step's end are all reported by now; those of the last step wait
  // one more, so that an MCU stop the run loop reports after this step still drops what it
  // stamped past its end, as console.log does.
  const std::int64_t known = world_ns_;
  world_ns_ = w.time_ns;
  for (std::size_t m = 0; m < mcus_.size(); ++m) {
    take(m, known, false);
    settle(m, known - 1);
  }
  for (std::size_t i = 0; i < results_.size(); ++i) {
    if (results_[i].verdict != Verdict::Pending) continue;
    const Expectation& e = scenario_.expectations[i];
    Live& l = live_[i];
    const std::int64_t d = deadline(e);
    if (const auto* g = std::get_if<RegionExpect>(&e.what)) {
      if (l.robot < w.robot_xy_m.size() && w.time_ns <= d) {
        const Eigen::Vector2d xy = w.robot_xy_m[l.robot];
        // How far the chassis origin is from the region's edge; 0 inside a box.
        const double distance = g->shape == RegionExpect::Shape::Circle
                                    ? std::max(0.0, (xy - g->center_m).norm() - g->radius_m)
                                    : (xy - xy.cwiseMax(g->min_m).cwiseMin(g->max_m)).norm();
        const bool inside = g->shape == RegionExpect::Shape::Circle ? (xy - g->center_m).norm() <= g->radius_m
                                                                    : distance == 0.0;
        if (inside) {
          pass(i, w.time_ns);
          continue;
        }
        if (distance < l.closest_m) {
          l.closest_m = distance;
          l.closest_ns = w.time_ns;
        }
      }
      if (w.time_ns >= d) fail(i, d, region_seen(i));
    } else if (const auto* c = std::get_if<CollisionExpect>(&e.what)) {
      for (const CollisionEvent& hit : w.new_collisions) {
        if (hit.time_ns > d) break;
        const bool mine = hit.robot == e.robot || hit.other == e.robot;
        const std::string& other = hit.robot == e.robot ? hit.other : hit.robot;
        if (mine && (c->with.empty() || other == c->with)) {
          fail(i, hit.time_ns, fmt::format("touched '{}' at {}", other, seconds_text(hit.time_ns)));
          break;
        }
      }
      if (results_[i].verdict == Verdict::Pending && w.time_ns >= d) pass(i, d);
    }
  }
}

std::string ExpectationChecker::region_seen(std::size_t i) const {
  const auto& g = std::get<RegionExpect>(scenario_.expectations[i].what);
  const Live& l = live_[i];
  if (!std::isfinite(l.closest_m)) return "the world took no step in time";
  if (g.shape == RegionExpect::Shape::Circle)
    return fmt::format("the robot came no closer than {:.2f} m to ({}, {}), at {}", l.closest_m + g.radius_m,
                       g.center_m.x(), g.center_m.y(), seconds_text(l.closest_ns));
  return fmt::format("the robot came no closer than {:.2f} m to the box, at {}", l.closest_m,
                     seconds_text(l.closest_ns));
}

// ---- stops and the end ----

void ExpectationChecker::mcu_stopped(std::size_t mcu, std::int64_t time_ns, std::string why) {
  Mcu& s = mcus_[mcu];
  if (s.stop_ns != INT64_MAX) return;
  s.stop_ns = time_ns;
  s.stop_why = std::move(why);
  // Everything it did up to its stop is reported by now; nothing after it will come.
  take(mcu, time_ns, true);
  resolve_stop(mcu);
}

void ExpectationChecker::mcu_stopped(const std::string& mcu, std::int64_t time_ns, std::string why) {
  for (std::size_t m = 0; m < mcus_.size(); ++m)
    if (mcus_[m].id == mcu) return mcu_stopped(m, time_ns, std::move(why));
}

void ExpectationChecker::resolve_stop(std::size_t m) {
  Mcu& s = mcus_[m];
  if (!s.line.empty()) end_line(m);
  settle(m, s.stop_ns);
  for (std::size_t i : by_mcu_[m]) {
    if (results_[i].verdict != Verdict::Pending) continue;
    const Expectation& e = scenario_.expectations[i];
    const auto* c = std::get_if<ConsoleExpect>(&e.what);
    if (c && c->never) pass(i, s.stop_ns);
    else if (std::holds_alternative<RunningExpect>(e.what))
      fail(i, s.stop_ns, fmt::format("{} at {}", s.stop_why, seconds_text(s.stop_ns)));
    else
      fail(i, s.stop_ns, fmt::format("the MCU stopped at {} ({}): {}", seconds_text(s.stop_ns), s.stop_why,
                                     seen_by(i, s.stop_ns)));
  }
}

void ExpectationChecker::finish(std::int64_t end_ns, bool interrupted) {
  for (std::size_t m = 0; m < mcus_.size(); ++m) {
    if (mcus_[m].stop_ns != INT64_MAX) continue;  // resolved at its stop
    take(m, end_ns, true);
    // A line still being printed when the run ends is cut short: only complete lines are judged,
    // or a `never` pattern written for whole lines could match its fragment.
    mcus_[m].line.clear();
    settle(m, end_ns);
  }
  for (std::size_t i = 0; i < results_.size(); ++i) {
    if (results_[i].verdict != Verdict::Pending) continue;
    const Expectation& e = scenario_.expectations[i];
    if (interrupted && deadline(e) > end_ns) continue;
    const std::int64_t at = std::min(deadline(e), end_ns);
    const auto* c = std::get_if<ConsoleExpect>(&e.what);
    if ((c && c->never) || std::holds_alternative<RunningExpect>(e.what) ||
        std::holds_alternative<CollisionExpect>(e.what))
      pass(i, at);
    else if (std::holds_alternative<RegionExpect>(e.what))
      fail(i, at, region_seen(i));
    else
      fail(i, at, seen_by(i, at));
  }
}

std::string failure_text(const ExpectationResult& result) {
  return fmt::format("expectation failed at {}: {}: {}", seconds_text(result.time_ns), result.expectation->name,
                     result.seen);
}

}  // namespace sear
