// When a run's output files are pushed to the disk: on a wall-clock period rather than at every
// step. A flush a step cost two write(2) calls a step, about 12 % of the simulator's time
// (issue 23); a period of 100 ms bounds what a simulator killed outright (SIGKILL) loses to the
// output of its last 100 ms of wall time. The run also flushes at every stop and at its end.
#pragma once

#include <chrono>

namespace sear {

class FlushClock {
 public:
  static constexpr std::chrono::milliseconds kPeriod{100};

  // True once a period has passed since it last said so (or since it was made). Reading the
  // clock costs tens of nanoseconds (vDSO), far below a step.
  bool due() {
    const auto now = std::chrono::steady_clock::now();
    if (now < next_) return false;
    next_ = now + kPeriod;
    return true;
  }

 private:
  std::chrono::steady_clock::time_point next_ = std::chrono::steady_clock::now() + kPeriod;
};

}  // namespace sear
