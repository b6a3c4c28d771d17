#include "view/replay_file.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "runtime/simulation.hpp"
#include "view/hello_message.hpp"
#include "view/mcu_panel_log.hpp"

namespace sear {
namespace {

constexpr std::int64_t kFlushEveryNs = 1'000'000'000;  // a simulated second
// A frame is written early once this many entries wait, so that the ring (kLogCapacity) never
// overwrites one the file has not taken: the other half is room for what one step logs (a
// console at 115200 baud prints at most ~12 lines a millisecond).
constexpr std::uint64_t kCatchUpEntries = kLogCapacity / 2;

gzFile as_gz(void* p) { return static_cast<gzFile>(p); }

}  // namespace

ReplayFile::ReplayFile(const std::string& path, const ProjectDesc& project, ViewModel& model, double rate_hz)
    : path_(path),
      model_(model),
      hello_(view_hello_json(project, "replay")),
      period_ns_(std::max<std::int64_t>(1, std::llround(1e9 / rate_hz))) {
  // zlib's gzip header carries no time stamp or file name: the bytes depend on the run alone.
  // Level 1: at zlib's default (6) compressing took ~7 % of the default project's run time for
  // a file a third smaller; at 1 it takes under 2 %.
  gz_ = gzopen(path.c_str(), "wb1");
  if (!gz_) throw ReplayError(fmt::format("sear: {}: cannot write the replay ({})", path, std::strerror(errno)));
  model_.keep_watching();  // the file takes every entry of the run, page or none
}

ReplayFile::~ReplayFile() {
  if (gz_) gzclose(as_gz(gz_));
}

void ReplayFile::write(const std::string& line) {
  if (failed_) return;
  const std::string text = line + "\n";
  if (gzwrite(as_gz(gz_), text.data(), static_cast<unsigned>(text.size())) != static_cast<int>(text.size())) {
    int code = 0;
    fmt::print(stderr, "sear: {}: the replay could not be written ({}); it stops here\n", path_,
               gzerror(as_gz(gz_), &code));
    failed_ = true;
  }
}

void ReplayFile::write_frame(const Simulation& sim) {
  write(model_.frame_json(sim, cursor_, ViewModel::kWholeStreams, ViewModel::kNoLimit));
  last_frame_ns_ = sim.time_ns();
}

void ReplayFile::start_run(const Simulation& sim) {
  if (!hello_written_) write(hello_);
  hello_written_ = true;
  write(model_.scene_json());
  cursor_ = FrameCursor{};
  write_frame(sim);
  next_frame_ns_ = sim.time_ns() + period_ns_;
  next_flush_ns_ = sim.time_ns() + kFlushEveryNs;
}

void ReplayFile::after_step(const Simulation& sim) {
  const std::int64_t t = sim.time_ns();
  if (t >= next_frame_ns_) {
    write_frame(sim);
    while (next_frame_ns_ <= t) next_frame_ns_ += period_ns_;
  } else if (model_.pending_entries(cursor_) >= kCatchUpEntries) {
    write_frame(sim);  // off the 1/rate grid: the log outruns the ring
  }
  if (t >= next_flush_ns_) {
    if (!failed_) gzflush(as_gz(gz_), Z_SYNC_FLUSH);
    while (next_flush_ns_ <= t) next_flush_ns_ += kFlushEveryNs;
  }
}

void ReplayFile::end_segment(const Simulation& sim) {
  if (last_frame_ns_ != sim.time_ns() || model_.pending_entries(cursor_) > 0) write_frame(sim);
  if (!failed_) gzflush(as_gz(gz_), Z_SYNC_FLUSH);
}

void ReplayFile::finish(const Simulation& sim) { end_segment(sim); }

}  // namespace sear
