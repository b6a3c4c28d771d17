// The per-robot CSV trace of a run: pose, velocities, wheel speeds and actuator commands,
// sampled at the trace rate, one file per robot, flushed row by row so a crash loses nothing.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "runtime/simulation.hpp"

namespace sear {

class TraceCsv {
 public:
  // Opens `folder`/trace_<robot>.csv for every robot and writes the header lines.
  TraceCsv(const std::string& folder, const Simulation& sim);
  void write_row(const Simulation& sim);
  void flush();
  const std::vector<std::string>& files() const { return paths_; }

 private:
  struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::vector<std::unique_ptr<std::FILE, FileCloser>> files_;
  std::vector<std::string> paths_;
};

}  // namespace sear
