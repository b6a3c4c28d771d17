// The one process of a run that outlives the simulator, only to kill what the run started. A
// simulator killed outright (SIGKILL from a CI runner's timeout) runs no clean-up code of its own;
// the keeper holds the read end of a pipe whose write end only the simulator has, and when that
// pipe closes, however the simulator ended, it kills every process group it was told of: each
// MCU's firmware with anything the firmware forked, and a compiler still running.
#pragma once

#include <sys/types.h>

namespace sear {

// Forks the keeper, if it is not running yet; a run calls it first thing, before it compiles or
// starts any firmware. Safe to call from a single-threaded process only.
void keeper_start();
// Tells the keeper of a process group to kill if the simulator dies (starting it if need be).
void keeper_watch(pid_t process_group);
// The group is gone (killed and reaped): its number may be reused, so the keeper forgets it.
void keeper_forget(pid_t process_group);

}  // namespace sear
