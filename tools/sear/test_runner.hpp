// Runs child processes (one `sear run` per test case), a bounded number at once, and reports each as
// it ends. A stop request (Ctrl-C, SIGTERM, SIGHUP) starts nothing more and is passed on to the
// running children, which end cleanly with their files complete.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace sear {

struct ChildRun {
  std::vector<std::string> argv;  // argv[0] is the program's path
  std::string cwd;                // the child's working folder
  std::string log;                // its stdout and stderr go to this file
};

// Runs every child, at most `jobs` at once, in the order given; calls `done(index, code)` in this
// process as each ends: its exit code, 128 + the signal that killed it, or 127 when it could not
// be started. Returns false when a stop request left some children unstarted.
bool run_children(const std::vector<ChildRun>& children, std::size_t jobs,
                  const std::function<void(std::size_t, int)>& done);

}  // namespace sear
