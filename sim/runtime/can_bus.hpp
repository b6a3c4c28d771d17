// One simulated classical CAN bus (ISO 11898-1): nodes queue frames, the bus decides who wins
// arbitration, when each frame is on the wire (bit stuffing included), whether anyone acked it,
// and keeps each node's error counters.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "runtime/can_frame.hpp"

namespace sear {

// One frame's time on the wire, as a node asked for it.
struct CanTransfer {
  std::int64_t start_ns = 0;  // SOF
  // Acked: end of EOF, when every node holds the frame. Not acked: end of the error delimiter.
  std::int64_t end_ns = 0;
  std::size_t node = 0;  // the sender
  CanFrame frame;
  std::uint64_t tag = 0;  // the sender's, from request()
  bool acked = false;     // false: an ACK error, the sender tries again
};

// Values as hal/can.h's enum can_state.
enum class CanErrorState : std::uint8_t { active = 0, passive = 1, bus_off = 2 };

struct CanCounters {
  std::uint16_t tec = 0;  // transmit error counter
  std::uint16_t rec = 0;  // receive error counter
  CanErrorState state = CanErrorState::active;
  // Failed attempts not reported as transfers (see CanBus::kReportedFailures).
  std::uint64_t unreported_failures = 0;
};

// Rules (ISO 11898-1 where it decides, our choices where it leaves the bus to physics):
// - Bit times: the bus keeps a bit grid that restarts at each SOF that follows an idle bus (hard
//   synchronisation); a frame that starts right after intermission continues the grid. A time
//   `b` bits into the grid is anchor + round(b * 1e9 / bitrate) ns (half up), so 83.333 kbit/s
//   never drifts however many frames follow each other.
// - Arbitration: when the bus becomes idle (end of intermission), or at the first request while
//   it is idle, every node whose oldest frame is ready by then starts; the lowest arbitration
//   field wins bit by bit: standard ID(11) RTR IDE, extended ID-A(11) SRR IDE ID-B(18) RTR.
//   Two nodes with the same arbitration field (only possible with the same ID and kind): on a
//   real bus identical frames merge and differing data gives bit errors; here the lower node
//   index wins and the other waits for the next arbitration, which keeps the run deterministic.
// - ACK: a frame is acked when another node that listens exists (set_listening) as it starts. A
//   node that only sends does not listen unless told to.
// - Errors: only ACK errors happen (no noise is simulated). The sender's TEC += 8 and it sends
//   a 6-bit error flag and an 8-bit error delimiter from the bit after the ACK slot, then 3
//   bits of intermission. An error-passive sender's TEC does not rise on an ACK error (the
//   ISO 11898-1 exception for a lone node), so it stays error passive and never goes bus off; it
//   waits 8 more bits after any frame it sent (suspend transmission) before it may start again,
//   giving other nodes the bus. A success lowers the sender's TEC and each listener's REC by 1
//   (not below 0). The error frame's 6 + 8 bits are the least ISO 11898-1 allows: with no
//   receiver there is no second error flag to lengthen the first.
// - Decisions: run_until(t_end) decides every frame whose SOF is before t_end and reports it at
//   once, even when it ends after t_end; the caller hands it on when its end_ns comes. Requests
//   for times before the last t_end are a programming error (std::logic_error): the bus has
//   already decided that past. set_listening and clear apply to frames that start from then on.
class CanBus {
 public:
  // Failed attempts at one frame reported as transfers; later ones (a lone error-passive node
  // repeating its frame forever) are only counted, so that a long run_until stays cheap.
  static constexpr std::uint64_t kReportedFailures = 32;
  // Times are clamped to this (about 146 years), far from int64 overflow.
  static constexpr std::int64_t kMaxTimeNs = INT64_MAX / 2;

  // Throws std::invalid_argument for 0 or a rate above 1 Mbit/s (classical CAN's maximum).
  explicit CanBus(std::uint32_t bitrate);

  std::uint32_t bitrate() const { return bitrate_; }
  std::size_t add_node(std::string name);
  std::size_t node_count() const { return nodes_.size(); }
  const std::string& node_name(std::size_t node) const { return nodes_.at(node).name; }

  // A listening node acks others' frames and counts as their receiver.
  void set_listening(std::size_t node, bool listening);
  // The node's controller is ready to send `frame` from time_ns on, after its earlier requests.
  // time_ns must not go back for one node nor lie before the last run_until's t_end.
  void request(std::size_t node, std::int64_t time_ns, const CanFrame& frame, std::uint64_t tag);
  // Drops the node's frames not yet started (its MCU stopped or reset its controller).
  void clear(std::size_t node);
  void run_until(std::int64_t t_end, std::vector<CanTransfer>& done);

  CanCounters counters(std::size_t node) const;
  std::size_t pending(std::size_t node) const { return nodes_.at(node).queue.size(); }
  // End of the last decided frame's intermission (error frames included): the bus is free.
  std::int64_t idle_at_ns() const { return time_at(idle_bits_); }
  std::int64_t horizon_ns() const { return horizon_; }
  // The time `bits` bit times after a hard synchronisation at start_ns.
  std::int64_t after_bits(std::int64_t start_ns, std::int64_t bits) const;

 private:
  struct Request {
    std::int64_t time_ns;
    CanFrame frame;
    std::uint64_t tag;
    std::uint32_t arbitration;  // lower wins
    int wire_bits;              // SOF .. EOF
  };
  struct Node {
    std::string name;
    bool listening = false;
    std::deque<Request> queue;
    std::uint16_t tec = 0;
    std::uint16_t rec = 0;
    bool suspended = false;  // error passive after its last frame: 8 more bits before it starts
    std::uint64_t failures_in_a_row = 0;
    std::uint64_t unreported_failures = 0;
  };

  std::int64_t time_at(std::int64_t grid_bits) const;
  // Moves whole seconds of bits into the anchor so that grid bit counts stay small.
  void normalise_grid();
  bool acked_by_other(std::size_t sender) const;
  // A failed attempt from a lone error-passive sender repeats unchanged until another node's
  // request is ready or t_end: skips those attempts arithmetically, reporting the first few.
  void repeat_failures(std::size_t sender, std::int64_t sof_bits, std::int64_t t_end, std::vector<CanTransfer>& done);
  void report_failure(Node& n, const Request& r, std::size_t sender, std::int64_t sof_bits,
                      std::vector<CanTransfer>& done);

  std::uint32_t bitrate_;
  std::vector<Node> nodes_;
  std::size_t queued_ = 0;  // over all nodes: an idle bus returns from run_until at once
  std::int64_t horizon_ = 0;
  std::int64_t anchor_ns_ = 0;  // last hard synchronisation
  std::int64_t idle_bits_ = 0;  // bits after the anchor when the bus is free again
};

}  // namespace sear
