#include "view/view_session.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <thread>

#include "runtime/simulation.hpp"
#include "runtime/stop_request.hpp"
#include "runtime/while_waiting.hpp"
#include "scene/description.hpp"
#include "view/hello_message.hpp"

namespace sear {
namespace {

// A page draws at most this many frames a second; more would only cost the run.
constexpr double kFramesPerSecond = 20;
// Of each LMS2xx or other binary UART stream, the telegrams a live frame shows: the page keeps a
// few hundred lines, and putting the ~90 an LMS200 sends per frame at 35x real time into JSON cost
// the run ~4 % (perf, default project).
constexpr std::size_t kStreamEntriesPerFrame = 8;
// The clock is read every this many steps while a page is connected: at 1 ms steps and up to
// ~100x real time, a frame is then late by at most ~0.04 ms of wall time per step checked.
constexpr unsigned kStepsPerLook = 4;
// How long a held or paced run sleeps between looks at the pages' commands and Ctrl-C.
constexpr auto kHoldPoll = std::chrono::milliseconds(5);
// A press of U or ArrowUp (ArrowDown) adds (takes) this much PWM duty; a page repeating the key
// while it is held goes on adding.
constexpr double kDutyPerPress = 0.25;
// Held H/K (or ArrowLeft/ArrowRight) spin the robot: this much duty is taken from the inner side
// and added to the outer one, so that at a standstill the robot turns on the spot.
constexpr double kSpinDuty = 0.5;
template <typename Duration>
double seconds(Duration d) { return std::chrono::duration<double>(d).count(); }

}  // namespace

// The keys' hold on one robot's motors.
struct ViewSession::KeyDrive {
  std::string robot;
  std::size_t index = 0;
  bool has_mcu = false;
  std::vector<int> side;  // per motor: +1 its wheels are on the left (y > 0), -1 right, 0 centred
  double throttle = 0;    // -1 (full reverse) .. 1 (full forward)
  bool left = false, right = false, brake = false;
};

ViewSession::ViewSession(const ProjectDesc& project, ViewModel& model, const ViewSessionOptions& options)
    : model_(model),
      server_(std::make_unique<ViewServer>(options.server)),
      speed_(options.speed),
      waiting_start_(options.wait_for_start),
      wait_for_page_s_(options.wait_for_page_s) {
  paused_ = waiting_start_;
  for (std::size_t r = 0; r < project.robots.size(); ++r) {
    const RobotDesc& rd = project.robots[r];
    KeyDrive k;
    k.robot = rd.name;
    k.index = r;
    k.has_mcu = !rd.mcus.empty();
    for (const MotorDesc& m : rd.motors) {
      double y = 0;
      for (const std::string& w : m.wheels)
        for (const WheelDesc& wd : rd.wheels)
          if (wd.name == w) y += wd.position_m.y();
      k.side.push_back(y > 1e-6 ? 1 : y < -1e-6 ? -1 : 0);
    }
    keys_.push_back(std::move(k));
  }
  server_->set_hello(view_hello_json(project, "live"));
}

ViewSession::~ViewSession() = default;

void ViewSession::start_run(Simulation& sim) {
  server_->set_scene(model_.scene_json());
  model_.set_watching(server_->has_clients());
  cursor_ = FrameCursor{};
  for (KeyDrive& k : keys_) {
    k.throttle = 0;
    k.left = k.right = k.brake = false;
  }
  reset_ = ended_ = holding_ = false;
  end_reason_.clear();
  steps_left_ = 0;
  rate_wall_ = Clock::now();
  rate_sim_s_ = sim.time_s();
  pace_.anchor(sim.time_s());
  if (server_->has_clients()) send_state(sim);
}

std::string ViewSession::status_json(double t_s) const {
  std::string reason = end_reason_;
  const bool waiting = !ended_ && waiting_start_;
  if (waiting) reason = "press Space or Start to begin";
  const nlohmann::json status = {{"type", "status"},   {"t", std::round(t_s * 1e6) / 1e6},
                                 {"paused", paused_},  {"waiting", waiting}, {"speed", speed_},
                                 {"rtf", std::round(rtf_ * 100) / 100},
                                 {"ended", ended_},    {"reason", reason}};
  return status.dump();
}

void ViewSession::send_state(const Simulation& sim) {
  const auto now = Clock::now();
  const double wall = seconds(now - rate_wall_);
  if (wall > 0 && !holding_) rtf_ = (sim.time_s() - rate_sim_s_) / wall;
  if (holding_) rtf_ = 0;
  rate_wall_ = now;
  rate_sim_s_ = sim.time_s();
  next_frame_ = now + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1 / kFramesPerSecond));
  // A page that connected since the last frame gets the log the ring still holds (its newest
  // entries, the console lines said before it came); pages already watching skip, by their
  // numbers, the entries they had.
  const bool new_page = server_->connections() != connections_seen_;
  if (new_page) cursor_ = model_.recent_cursor();
  connections_seen_ = server_->connections();
  server_->send_frame(model_.frame_json(sim, cursor_, new_page ? ViewModel::kWholeStreams : kStreamEntriesPerFrame),
                      status_json(sim.time_s()));
}

ViewSession::Gate ViewSession::before_step(Simulation& sim) {
  if (wait_for_page_s_ > 0) {
    // Once, before the first step: a run shorter than a browser's start-up would be over before
    // anyone saw it.
    const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(wait_for_page_s_));
    wait_for_page_s_ = 0;
    while (!server_->has_clients() && !stop_requested() && Clock::now() < until) std::this_thread::sleep_for(kHoldPoll);
    if (server_->has_clients()) send_state(sim);  // the page sees where it starts, t = 0
    pace_.anchor(sim.time_s());
  }
  for (;;) {
    if (server_->has_commands())
      for (const ViewCommand& c : server_->take_commands()) {
        apply(c, sim);
        if (server_->has_clients()) server_->send_status(status_json(sim.time_s()));
      }
    if (reset_) return Gate::Reset;
    if (stop_requested()) return Gate::Stop;
    if (paused_) {
      // Held: the pages see the state held at, and a page that connects meanwhile sees it too.
      if (!holding_ || server_->connections() != connections_seen_) {
        holding_ = true;
        if (server_->has_clients()) send_state(sim);
      }
      while_waiting();
      std::this_thread::sleep_for(kHoldPoll);
      continue;
    }
    if (holding_) {
      holding_ = false;
      pace_.anchor(sim.time_s());
    }
    if (speed_ <= 0) break;
    // Never ahead of the wall clock times the speed. A slow speed waits long (a 1 ms step at
    // 0.001x: a second), so it waits in slices, the commands and Ctrl-C looked at between them.
    const double ahead_s = pace_.ahead_s(sim.time_s(), speed_);
    if (ahead_s <= 0) break;
    if (server_->connections() != connections_seen_ && server_->has_clients()) send_state(sim);
    while_waiting();
    std::this_thread::sleep_for(std::chrono::duration<double>(std::min(ahead_s, seconds(kHoldPoll))));
  }
  if (steps_left_ > 0 && --steps_left_ == 0) paused_ = true;  // this is the last step asked for
  return Gate::Step;
}

void ViewSession::after_step(const Simulation& sim) {
  // Serial traffic is decoded only while a page watches (or a replay is written): no page, no cost.
  const bool watched = server_->has_clients();
  model_.set_watching(watched);
  if (!watched) return;
  if (++steps_since_look_ < kStepsPerLook) return;
  steps_since_look_ = 0;
  if (Clock::now() < next_frame_) return;
  send_state(sim);
}

ViewSession::Gate ViewSession::end_run(const Simulation& sim, const std::string& reason, bool keep_serving) {
  ended_ = true;
  paused_ = false;
  waiting_start_ = false;
  end_reason_ = reason;
  holding_ = true;
  if (server_->has_clients()) send_state(sim);
  if (!keep_serving) {
    // A moment for the last frame to reach the pages before the server closes.
    if (server_->has_clients()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    return Gate::Stop;
  }
  Simulation& held = const_cast<Simulation&>(sim);  // only keys reach it, and they move nothing now
  for (;;) {
    if (server_->has_commands())
      for (const ViewCommand& c : server_->take_commands()) {
        apply(c, held);
        if (reset_) return Gate::Reset;
        if (server_->has_clients()) server_->send_status(status_json(sim.time_s()));
      }
    if (stop_requested()) return Gate::Stop;
    if (server_->connections() != connections_seen_ && server_->has_clients()) send_state(sim);
    std::this_thread::sleep_for(kHoldPoll);
  }
}

void ViewSession::apply(const ViewCommand& c, Simulation& sim) {
  switch (c.kind) {
    case ViewCommand::Kind::Pause:
      paused_ = true;
      steps_left_ = 0;
      break;
    case ViewCommand::Kind::Resume:
    case ViewCommand::Kind::Start:
      // Start ends the wait at t = 0; resume does too, and ends a pause.
      if (c.kind == ViewCommand::Kind::Resume || waiting_start_) paused_ = false;
      waiting_start_ = false;
      steps_left_ = 0;
      break;
    case ViewCommand::Kind::Step:
      if (ended_) break;
      waiting_start_ = false;
      paused_ = false;
      steps_left_ = c.steps;
      break;
    case ViewCommand::Kind::Reset:
      reset_ = true;
      break;
    case ViewCommand::Kind::Speed:
      speed_ = c.factor;
      pace_.anchor(sim.time_s());
      break;
    case ViewCommand::Kind::Key:
      drive(c, sim);
      break;
  }
}

void ViewSession::drive(const ViewCommand& c, Simulation& sim) {
  if (c.key == "Enter") {
    if (c.down) reset_ = true;
    return;
  }
  KeyDrive* k = nullptr;
  for (KeyDrive& candidate : keys_)
    if (c.robot.empty() ? !candidate.has_mcu : candidate.robot == c.robot) {
      k = &candidate;
      break;
    }
  if (!k || k->has_mcu) {
    const std::string who = c.robot.empty() ? std::string() : c.robot;
    if (warned_.insert(who).second) {
      if (!k && who.empty())
        fmt::print(stderr, "sear: every robot has an MCU, which drives its motors: the viewer's keys are ignored\n");
      else if (!k)
        fmt::print(stderr, "sear: the viewer's keys name robot '{}', which this project does not have\n", who);
      else
        fmt::print(stderr, "sear: robot '{}' has an MCU, which drives its motors: the viewer's keys are ignored\n",
                   k->robot);
    }
    return;
  }
  if (ended_ || sim.robot_stopped(k->index)) return;
  if (c.key == "h" || c.key == "ArrowLeft") k->left = c.down;
  if (c.key == "k" || c.key == "ArrowRight") k->right = c.down;
  if (c.down && (c.key == "u" || c.key == "ArrowUp")) {
    k->brake = false;
    k->throttle = std::min(1.0, k->throttle + kDutyPerPress);
  }
  if (c.down && c.key == "ArrowDown") {
    k->brake = false;
    k->throttle = std::max(-1.0, k->throttle - kDutyPerPress);
  }
  if (c.down && c.key == "j") {
    k->brake = true;
    k->throttle = 0;
  }
  const int turn = (k->left ? 1 : 0) - (k->right ? 1 : 0);  // +1: counter-clockwise, to the left
  Vehicle& v = sim.robot(k->index);
  for (std::size_t m = 0; m < k->side.size(); ++m) {
    const double duty = k->throttle - k->side[m] * turn * kSpinDuty;
    DcMotorCommand command;
    if (std::fabs(duty) < 1e-9) {
      command.direction = k->brake ? MotorDirection::Brake : MotorDirection::Coast;
    } else {
      command.direction = duty > 0 ? MotorDirection::Forward : MotorDirection::Reverse;
      command.duty = std::min(1.0, std::fabs(duty));
    }
    v.command_motor(m, command);
  }
}

}  // namespace sear
