// What `sear run --view` and `sear view` add to a run: the viewer's server, fed frames of the run
// as often as a page can watch them, and the pages' commands (pause, step, reset, speed, start,
// keys) applied between steps. With no page connected and no speed asked for, it costs three
// flag loads per step (commands waiting, Ctrl-C, a page connected), no clock read.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "runtime/wall_pace.hpp"
#include "view/view_model.hpp"
#include "view/view_server.hpp"

namespace sear {

class Simulation;
struct ProjectDesc;

struct ViewSessionOptions {
  ViewServerOptions server;
  double speed = 0;             // times real time; 0: as fast as possible
  bool wait_for_start = false;  // hold at t = 0 until a page says start
  double wait_for_page_s = 0;   // hold at t = 0 until a page connects, at most this long (wall)
};

class ViewSession {
 public:
  // Starts the server (ViewServerError when it cannot listen). `model` is the run's tap.
  ViewSession(const ProjectDesc& project, ViewModel& model, const ViewSessionOptions& options);
  ~ViewSession();
  ViewSession(const ViewSession&) = delete;
  ViewSession& operator=(const ViewSession&) = delete;

  const ViewServer& server() const { return *server_; }

  // A run, or one started over by a reset, begins at t = 0 with `sim` (the model restarted).
  void start_run(Simulation& sim);

  enum class Gate {
    Step,   // go on with the next step
    Stop,   // a stop was requested (Ctrl-C) while held
    Reset,  // a page asked to start over at t = 0
  };
  // Before each step: applies the pages' commands, holds while paused or waiting to start, and
  // paces the run at the speed asked for.
  Gate before_step(Simulation& sim);
  // After each step: a frame and a status for the pages, at most 20 a second of wall time, and
  // only while a page is connected.
  void after_step(const Simulation& sim);
  // The run is over (`reason`, as the summary's status): its last state goes out. With
  // `keep_serving`, serves that state until Ctrl-C (Stop) or a page's reset (Reset).
  Gate end_run(const Simulation& sim, const std::string& reason, bool keep_serving);

 private:
  using Clock = std::chrono::steady_clock;
  struct KeyDrive;

  void apply(const ViewCommand& command, Simulation& sim);
  void drive(const ViewCommand& command, Simulation& sim);
  void send_state(const Simulation& sim);
  std::string status_json(double t_s) const;

  ViewModel& model_;
  std::unique_ptr<ViewServer> server_;
  FrameCursor cursor_;
  std::vector<KeyDrive> keys_;
  std::set<std::string> warned_;  // robots whose keys were refused, told once each
  double speed_;
  bool waiting_start_;
  double wait_for_page_s_;  // before the first step only
  bool paused_ = false;
  bool holding_ = false;  // before_step is holding: the pages were sent the state it holds at
  bool reset_ = false;
  bool ended_ = false;
  std::string end_reason_;
  std::int64_t steps_left_ = 0;  // "step n": steps still to go before pausing
  unsigned steps_since_look_ = 0;
  Clock::time_point next_frame_{};
  std::uint64_t connections_seen_ = 0;
  // The rate of the run, over the time between two frames.
  Clock::time_point rate_wall_{};
  double rate_sim_s_ = 0, rtf_ = 0;
  WallPace pace_;  // at speed_
};

}  // namespace sear
