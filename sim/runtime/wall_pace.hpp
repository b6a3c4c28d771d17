// Keeping a run no faster than a multiple of real time (`--realtime`, the viewer's speed): how far
// the simulation is ahead of the wall clock. One reference for both, so they lag and catch up alike.
#pragma once

#include <chrono>

namespace sear {

class WallPace {
 public:
  // Sim time sim_s is now on the wall clock.
  void anchor(double sim_s) {
    wall_ = Clock::now();
    sim_s_ = sim_s;
  }
  // Wall seconds to wait before sim time sim_s, at `speed` times real time; <= 0: none. A run that
  // fell behind by more than 0.1 s (paused, or slower than asked) is anchored again where it is
  // rather than racing to catch up.
  double ahead_s(double sim_s, double speed) {
    const double ahead = (sim_s - sim_s_) / speed - std::chrono::duration<double>(Clock::now() - wall_).count();
    if (ahead < -kMaxLag_s) anchor(sim_s);
    return ahead;
  }

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr double kMaxLag_s = 0.1;
  Clock::time_point wall_ = Clock::now();
  double sim_s_ = 0;
};

}  // namespace sear
