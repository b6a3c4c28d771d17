// The line is kept as the sender's frames (a piecewise-constant level); the receiver hunts for
// start edges on it and samples it at its own bit times.
#include "runtime/serial_wire.hpp"

#include <algorithm>
#include <limits>

namespace sear {

namespace {

constexpr int64_t kNsPerS = 1000000000;

// Offset of `n32` thirty-seconds of a bit at `baud` from the frame's start edge, rounded to the
// nearest ns. Computed from the start each time so errors never accumulate along a frame.
int64_t bit32_ns(int64_t n32, uint32_t baud) {
  return (n32 * kNsPerS + 16 * static_cast<int64_t>(baud)) / (32 * static_cast<int64_t>(baud));
}

// Start of bit j (0 = start bit, 1..8 = data LSB first, 9 = stop, 10 = end of frame).
int64_t bit_ns(int j, uint32_t baud) { return bit32_ns(32 * j, baud); }

// Logic level of bit j of an 8N1 frame carrying `value`, before any inversion.
int logic_bit(int j, uint8_t value) {
  if (j == 0) return 0;
  if (j >= 9) return 1;
  return (value >> (j - 1)) & 1;
}

// Where the receiver samples, in 32nds of its bit from the start edge. Its 16x sample clock sees
// the edge at its first low sample ("sample 1"), 0 to 1/16 bit after the edge, on average 1/32;
// it votes with samples 8, 9 and 10 counted from there, and we read the line at the middle one:
// 1/32 + 8/16 = 17/32 into each bit. A new start edge is accepted right after the stop bit's
// last voting sample ("can come right after the last of the bits used for majority voting"):
// 1/32 + 9/16 = 19/32 into the stop bit, and likewise after a start bit rejected as a spike.
constexpr int64_t mid_bit32(int j) { return 32 * j + 17; }
constexpr int64_t kMidStart32 = mid_bit32(0);
constexpr int64_t kAfterSpike32 = 19;
constexpr int64_t kStopSample32 = mid_bit32(9);
constexpr int64_t kHuntAgain32 = 32 * 9 + 19;

}  // namespace

SerialWire::SerialWire(bool inverted) : inverted_(inverted) {}

void SerialWire::send(const serial_byte& byte) {
  if (byte.baud == 0) return;  // a frame of no duration cannot be on a line
  // One sender's frames never overlap. A rate that is not a whole baud (an AVR's 9615.4 for
  // 9600: f / (8 (UBRR + 1))) reaches the line rounded, and its back-to-back frames, stamped at the
  // true rate, would each seem to start a few ns before the one before it ended: that start edge
  // would fall behind where the receiver resumed hunting, and the byte would be read from the
  // middle. The sender started it when the one before it ended.
  const int64_t start = std::max(byte.end_ns - serial_frame_ns(byte.baud), last_end_ns_);
  frames_.push_back(Frame{start, byte.end_ns, byte.baud, byte.value});
  last_end_ns_ = std::max(last_end_ns_, byte.end_ns);
  last_sender_baud_ = byte.baud;
}

void SerialWire::set_baud(std::vector<BaudChange>& list, uint32_t baud, int64_t from_ns) {
  // A later change at the same time replaces the earlier; out-of-order ones are clamped so the
  // list stays sorted (the contract asks for time order).
  while (!list.empty() && list.back().from_ns >= from_ns) list.pop_back();
  list.push_back(BaudChange{from_ns, baud});
}

void SerialWire::set_receiver_baud(uint32_t baud, int64_t from_ns) { set_baud(bauds_, baud, from_ns); }

void SerialWire::set_sender_baud(uint32_t baud, int64_t from_ns) { set_baud(sender_bauds_, baud, from_ns); }

int64_t SerialWire::known_until(int64_t until_ns) const {
  if (sender_bauds_.empty()) {
    if (last_sender_baud_ == 0) return std::numeric_limits<int64_t>::min();  // nothing sent, nothing known
    return std::max(last_end_ns_, until_ns - serial_frame_ns(last_sender_baud_));
  }
  // A frame not yet sent starts after the last one sent ended, at the rate in force at its start:
  // any rate in force between then and until_ns. The slowest gives the longest frame.
  int64_t longest = 0;
  for (size_t i = 0; i < sender_bauds_.size(); ++i) {
    const BaudChange& c = sender_bauds_[i];
    if (c.from_ns >= until_ns) break;
    const bool over_before_last_end = i + 1 < sender_bauds_.size() && sender_bauds_[i + 1].from_ns <= last_end_ns_;
    if (over_before_last_end || c.baud == 0) continue;
    longest = std::max(longest, serial_frame_ns(c.baud));
  }
  return std::max(last_end_ns_, until_ns - longest);
}

uint32_t SerialWire::baud_at(int64_t t_ns) const {
  uint32_t baud = 0;
  for (const BaudChange& c : bauds_) {
    if (c.from_ns > t_ns) break;
    baud = c.baud;
  }
  return baud;
}

int64_t SerialWire::receiver_baud_until(int64_t t_ns) const {
  for (const BaudChange& c : bauds_)
    if (c.from_ns > t_ns) return c.from_ns;
  return std::numeric_limits<int64_t>::max();
}

int SerialWire::level_at(int64_t t_ns) const {
  const int mark = inverted_ ? 0 : 1;
  // First frame ending after t: frames are in time order and do not overlap.
  auto it = std::upper_bound(frames_.begin(), frames_.end(), t_ns,
                             [](int64_t t, const Frame& f) { return t < f.end_ns; });
  if (it == frames_.end() || it->start_ns > t_ns) return mark;
  int j = 9;
  while (j > 0 && it->start_ns + bit_ns(j, it->baud) > t_ns) --j;
  const int level = logic_bit(j, it->value);
  return inverted_ ? 1 - level : level;
}

int64_t SerialWire::next_falling_edge(int64_t from_ns, int64_t limit_ns) const {
  const int mark = inverted_ ? 0 : 1;
  auto it = std::upper_bound(frames_.begin(), frames_.end(), from_ns,
                             [](int64_t t, const Frame& f) { return t < f.end_ns; });
  for (; it != frames_.end() && it->start_ns < limit_ns; ++it) {
    // The level before a frame's start is always mark: idle, or the previous frame's stop bit.
    int before = mark;
    for (int j = 0; j <= 9; ++j) {
      const int logic = logic_bit(j, it->value);
      const int after = inverted_ ? 1 - logic : logic;
      const int64_t t = it->start_ns + bit_ns(j, it->baud);
      if (t >= limit_ns) return std::numeric_limits<int64_t>::max();
      if (t >= from_ns && before == 1 && after == 0) return t;
      before = after;
    }
    // The frame ends in its stop bit (mark) and the line stays at mark: no edge at its end.
  }
  return std::numeric_limits<int64_t>::max();
}

const SerialWire::FrameTimes& SerialWire::times(uint32_t baud) const {
  if (times_.baud != baud) times_ = FrameTimes{baud, bit_ns(9, baud), serial_frame_ns(baud), bit32_ns(kHuntAgain32, baud)};
  return times_;
}

void SerialWire::decode(int64_t known_until_ns) {
  const int64_t none = std::numeric_limits<int64_t>::max();
  // The first frame that ends after scan_from_ns_: both only move on here (frames_ changes
  // after the loop), so a walk replaces a search a byte, and the per-baud offsets are worked out
  // once a rate rather than with three 64-bit divisions a byte (a 500 kbaud line brings 50 a ms).
  std::size_t after = 0;
  while (scan_from_ns_ < known_until_ns) {
    while (after < frames_.size() && frames_[after].end_ns <= scan_from_ns_) ++after;
    // The common case, matching ends, without searching the line: the first frame still on it
    // starts once the receiver hunts again (every frame before it is over, so the line idles at
    // mark until its start bit), at the receiver's rate and in normal polarity. It is read as
    // sent, exactly as the search below would read it.
    // Back-to-back bytes: the hunt resumes within the stop bit of the frame just read, whose
    // line holds mark to its end, so the first frame with an edge left is the one after it.
    if (!inverted_) {
      std::size_t next = after;
      if (next < frames_.size() && frames_[next].start_ns < scan_from_ns_ &&
          scan_from_ns_ >= frames_[next].start_ns + times(frames_[next].baud).stop_bit_ns)
        ++next;
      if (next < frames_.size()) {
        const Frame& f = frames_[next];
        if (f.start_ns >= scan_from_ns_ && f.start_ns < known_until_ns && baud_at(f.start_ns) == f.baud) {
          // It, and the frames after it while each starts once the receiver hunts again, at the
          // same rate, before the receiver's next change of rate: the walk above would find each
          // the same way (the frame before it is over but for its stop bit), so a stream's run
          // of bytes is read here without it. Each ends as the search's would (its start edge
          // plus a frame), also a frame the sender started late, when the one before it ended.
          const FrameTimes& t = times(f.baud);
          const int64_t rate_until = receiver_baud_until(f.start_ns);
          std::size_t k = next;
          do {
            const Frame& g = frames_[k];
            ready_.push_back(serial_byte{g.start_ns + t.frame_ns, g.baud, g.value, {0, 0, 0}});
            scan_from_ns_ = g.start_ns + t.hunt_again_ns;
          } while (++k < frames_.size() && frames_[k].baud == f.baud && frames_[k].start_ns >= scan_from_ns_ &&
                   frames_[k].start_ns < known_until_ns && frames_[k].start_ns < rate_until);
          after = k - 1;  // the last frame read is still on the line
          continue;
        }
      }
    }
    const int64_t t0 = next_falling_edge(scan_from_ns_, known_until_ns);
    if (t0 == none) {
      scan_from_ns_ = known_until_ns;  // no edge before the horizon; later ones are found later
      break;
    }
    const uint32_t baud = baud_at(t0);
    if (baud == 0) {  // port not begun: the edge goes by unseen
      scan_from_ns_ = t0 + 1;
      continue;
    }
    const int64_t end = t0 + serial_frame_ns(baud);

    // Fast path: a frame that starts exactly here, at the receiver's rate, in normal polarity,
    // is read as sent (same value, same end).
    if (!inverted_) {
      auto it = std::lower_bound(frames_.begin(), frames_.end(), t0,
                                 [](const Frame& f, int64_t t) { return f.start_ns < t; });
      if (it != frames_.end() && it->start_ns == t0 && it->baud == baud) {
        ready_.push_back(serial_byte{end, baud, it->value, {0, 0, 0}});
        scan_from_ns_ = t0 + bit32_ns(kHuntAgain32, baud);
        continue;
      }
    }

    if (t0 + bit32_ns(kStopSample32, baud) >= known_until_ns) break;  // wait for more line
    if (level_at(t0 + bit32_ns(kMidStart32, baud)) != 0) {
      scan_from_ns_ = t0 + bit32_ns(kAfterSpike32, baud);  // a spike, not a start bit
      continue;
    }
    int value = 0;
    for (int bit = 0; bit < 8; ++bit) value |= level_at(t0 + bit32_ns(mid_bit32(bit + 1), baud)) << bit;
    if (level_at(t0 + bit32_ns(kStopSample32, baud)) == 0) ++framing_errors_;
    ready_.push_back(serial_byte{end, baud, static_cast<uint8_t>(value), {0, 0, 0}});
    scan_from_ns_ = t0 + bit32_ns(kHuntAgain32, baud);
  }
  forget_before(scan_from_ns_);
}

void SerialWire::forget_before(int64_t t_ns) {
  // Vectors rather than deques: a line holds a quantum's frames or so, and indexing a deque was
  // nearly half of reading a 500 kbaud line's bytes (callgrind).
  std::size_t over = 0;
  while (over < frames_.size() && frames_[over].end_ns <= t_ns) ++over;
  frames_.erase(frames_.begin(), frames_.begin() + static_cast<std::ptrdiff_t>(over));
  // The sender's rates before its last frame ended no longer bound anything still to come.
  while (sender_bauds_.size() > 1 && sender_bauds_[1].from_ns <= last_end_ns_) sender_bauds_.erase(sender_bauds_.begin());
}

void SerialWire::receive_until(int64_t until_ns, std::vector<serial_byte>& out) {
  const int64_t known = known_until(until_ns);
  if (known != std::numeric_limits<int64_t>::min()) decode(known);
  std::size_t due = 0;
  while (due < ready_.size() && ready_[due].end_ns < until_ns) ++due;
  out.insert(out.end(), ready_.begin(), ready_.begin() + static_cast<std::ptrdiff_t>(due));
  ready_.erase(ready_.begin(), ready_.begin() + static_cast<std::ptrdiff_t>(due));
}

}  // namespace sear
