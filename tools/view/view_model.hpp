// What the browser viewer shows of a run, as JSON messages (tools/view/PROTOCOL.md): the scene
// once, then frames of the state now with what was logged since the last frame. It only watches.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "runtime/run_tap.hpp"

namespace sear {

struct ProjectDesc;

// Where one stream of frames (the live page, a replay file) is in the log of console lines and
// UART messages; each stream keeps its own, so neither takes entries from the other.
struct FrameCursor {
  std::uint64_t next_entry = 0;
};

class ViewModel final : public RunTap {
 public:
  explicit ViewModel(const ProjectDesc& project);
  ~ViewModel() override;
  ViewModel(const ViewModel&) = delete;
  ViewModel& operator=(const ViewModel&) = delete;

  // The "scene" message: world, robots, their sensors and MCUs. Fixed for a run.
  const std::string& scene_json() const;
  // A "frame" message: the state of `sim` now, and the log entries after `cursor` (which it moves
  // on; at most the newest `max_entries`, the rest counted as dropped; a replay passes kNoLimit).
  // Of each UART stream that is not text (LMS telegrams, raw bytes), only the newest `stream_cap`
  // entries are kept (the live page's frames); the others are counted as dropped too.
  std::string frame_json(const Simulation& sim, FrameCursor& cursor, std::size_t stream_cap = kWholeStreams,
                         std::size_t max_entries = kMaxEntriesPerFrame);
  // Entries logged after `cursor` (since the last reset); more than kLogCapacity means some are
  // gone from the ring.
  std::uint64_t pending_entries(const FrameCursor& cursor) const;
  // A cursor at the newest kMaxEntriesPerFrame entries the ring holds since the last reset: a
  // frame from it, with whole streams, drops nothing (a page's first frame, its recent log).
  FrameCursor recent_cursor() const;
  // Whether a page watches (true until told otherwise). Not watching, the model neither decodes
  // UART traffic nor logs CAN frames: a run with no page connected pays for neither. Watching
  // again, each stream resumes at its next whole sentence or telegram. Console lines are always
  // logged, so that a page that connects late gets the recent ones.
  void set_watching(bool watching);
  // A replay file watches the whole run: set_watching(false) no longer stops the log.
  void keep_watching();
  bool watching() const;
  // A reset started the run over at t = 0: the MCUs' state and the log are cleared.
  void restart();
  // MCU `mcu_id` ("robot.mcu", as McuStop::mcu in Lockstep::stops()) stopped: its panel says why,
  // until a restart.
  void mcu_stopped(const std::string& mcu_id, const std::string& why);

  static constexpr std::size_t kMaxEntriesPerFrame = 400;
  static constexpr std::size_t kWholeStreams = SIZE_MAX;
  static constexpr std::size_t kNoLimit = SIZE_MAX;

  void on_mcu_events(std::size_t mcu, const sear_event* events, std::size_t count) override {
    for (std::size_t i = 0; i < count; ++i) on_mcu_event(mcu, events[i]);
  }
  void on_mcu_event(std::size_t mcu, const sear_event& event);
  void on_sample(std::size_t mcu, std::size_t device, const sear_link_sample& sample) override;
  void on_chip_cycles(std::size_t mcu, std::uint64_t cycles, std::uint64_t busy) override;
  void on_reading(std::size_t mcu, std::size_t device, std::int64_t time_ns, const double* values,
                  std::size_t count) override;
  void on_wire_bytes(std::size_t mcu, std::size_t device, bool from_device, const serial_byte* bytes,
                     std::size_t count) override;
  void on_can_frame(std::size_t bus, const CanTransfer& transfer) override;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace sear
