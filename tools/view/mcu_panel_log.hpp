// The viewer's log of what the MCUs said and heard (console lines, UART messages, CAN frames):
// entries numbered across the run, the newest kLogCapacity kept, read by each stream of frames
// from its own cursor.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "exporters/printable_text.hpp"

namespace sear {

constexpr std::size_t kLogCapacity = 4096;

struct LogEntry {
  enum class Kind : std::uint8_t { Console, Nmea, Lms, Bytes, Can };
  std::uint64_t seq = 0;
  std::int64_t t_ns = 0;
  Kind kind = Kind::Bytes;
  int mcu = -1;     // the MCU it belongs to; -1 for a CAN frame (all MCUs on `bus`)
  int device = -1;  // into the MCU's devices, for UART traffic
  int bus = -1;     // CAN
  bool from_device = false;
  int crc_ok = -1;  // -1: no checksum in this kind of message
  std::string text;
  std::string hex;
};

class LogRing {
 public:
  LogRing() : slots_(kLogCapacity) {}
  // A slot for the next entry, its sequence number set; the caller fills in the rest. The oldest
  // entry's strings are reused, so a full ring allocates only when a message outgrows them.
  LogEntry& add() {
    LogEntry& e = slots_[next_ % kLogCapacity];
    e.seq = next_++;
    e.mcu = e.device = e.bus = e.crc_ok = -1;
    e.from_device = false;
    e.text.clear();
    e.hex.clear();
    return e;
  }
  std::uint64_t next_seq() const { return next_; }
  std::uint64_t oldest_seq() const { return next_ > kLogCapacity ? next_ - kLogCapacity : 0; }
  const LogEntry& at(std::uint64_t seq) const { return slots_[seq % kLogCapacity]; }
  // Numbering goes on after a reset so that no cursor sees an old number again.
  void clear() { cleared_at_ = next_; }
  std::uint64_t cleared_at() const { return cleared_at_; }

 private:
  std::vector<LogEntry> slots_;
  std::uint64_t next_ = 0;
  std::uint64_t cleared_at_ = 0;
};

}  // namespace sear
