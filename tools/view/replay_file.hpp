// A run's replay (`sear run --replay FILE`): the viewer's messages, gzip-compressed, one JSON a
// line: hello, scene, then a frame every 1/rate simulated seconds (and between, when the log
// grows fast) with every log entry since the one before. Depends only on what the run computes, so the same project and seed give the same bytes.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "view/view_model.hpp"

namespace sear {

class Simulation;
struct ProjectDesc;

struct ReplayError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class ReplayFile {
 public:
  // Opens (truncates) `path`; throws ReplayError naming it when it cannot.
  ReplayFile(const std::string& path, const ProjectDesc& project, ViewModel& model, double rate_hz);
  ~ReplayFile();
  ReplayFile(const ReplayFile&) = delete;
  ReplayFile& operator=(const ReplayFile&) = delete;

  // A run, or one started over by a reset, begins at t = 0: the hello (the first time), the scene
  // and a frame of t = 0.
  void start_run(const Simulation& sim);
  // A frame when one is due, or sooner when the log has grown to half the ring since the last
  // (so that no entry is lost); the file flushed every simulated second, so that a run killed
  // leaves a readable prefix.
  void after_step(const Simulation& sim);
  // A reset is about to start the run over: the last state of this one, with what it logged since
  // the last frame, and everything flushed. start_run(sim) of the new run follows.
  void end_segment(const Simulation& sim);
  // The run ended: as end_segment().
  void finish(const Simulation& sim);

  static constexpr double kDefaultRateHz = 20;

 private:
  void write(const std::string& line);
  void write_frame(const Simulation& sim);

  std::string path_;
  ViewModel& model_;
  std::string hello_;
  void* gz_ = nullptr;  // gzFile, kept out of this header
  bool failed_ = false;
  FrameCursor cursor_;
  std::int64_t period_ns_;
  std::int64_t next_frame_ns_ = 0, next_flush_ns_ = 0, last_frame_ns_ = -1;
  bool hello_written_ = false;
};

}  // namespace sear
