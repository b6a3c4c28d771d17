// Work the simulator does whenever it waits on something outside the simulated world (a
// firmware's turn, an LCM controller, a paused viewer): the run's output files reach the disk on
// the wall clock's period even while no step ends for a long time.
#pragma once

#include <functional>

namespace sear {

// Installs `work` for its lifetime (one at a time; the run's outputs install theirs).
class WhileWaiting {
 public:
  explicit WhileWaiting(std::function<void()> work);
  ~WhileWaiting();
  WhileWaiting(const WhileWaiting&) = delete;
  WhileWaiting& operator=(const WhileWaiting&) = delete;
};

// Called by every loop of the run that can wait for long, beside stop_requested(), at least every
// 100 ms of waiting, on the thread that steps the world. Does nothing with nothing installed.
void while_waiting();

}  // namespace sear
