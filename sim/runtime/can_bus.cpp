#include "runtime/can_bus.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "runtime/can_bits.hpp"

namespace sear {

namespace {

__extension__ typedef __int128 Int128;  // bit counts times 1e9 outgrow int64 after ~2.5 h at 1 Mbit/s

constexpr std::int64_t kNsPerS = 1'000'000'000;
constexpr std::uint16_t kErrorPassiveTec = 128;
constexpr std::uint16_t kAckErrorTecStep = 8;
// From the bit after the ACK slot on, a failed frame is replaced by the error frame: the ACK
// delimiter and EOF are never sent.
constexpr int kAfterAckSlotBits = 1 + 7;

// The arbitration field as one number whose bits, MSB first, are the bits on the wire (0 =
// dominant), so the numerically lowest field wins. A standard field is 13 bits, padded with 0:
// it differs from any extended field by its IDE bit at the latest, so the padding never decides.
std::uint32_t arbitration_field(const CanFrame& f) {
  const std::uint32_t rtr = f.remote ? 1 : 0;
  if (!f.extended) return (f.id << 21) | (rtr << 20);
  return ((f.id >> 18) << 21) | (1u << 20) | (1u << 19) | ((f.id & 0x3FFFFu) << 1) | rtr;
}

void check_frame(const CanFrame& f) {
  if (f.dlc > 8) throw std::invalid_argument("CAN frame DLC " + std::to_string(f.dlc) + " is above 8");
  if (f.id > (f.extended ? 0x1FFFFFFFu : 0x7FFu))
    throw std::invalid_argument("CAN identifier " + std::to_string(f.id) + " does not fit its format");
}

}  // namespace

CanBus::CanBus(std::uint32_t bitrate) : bitrate_(bitrate) {
  if (bitrate == 0 || bitrate > 1'000'000)
    throw std::invalid_argument("CAN bit rate " + std::to_string(bitrate) + " is outside 1 bit/s .. 1 Mbit/s");
}

std::size_t CanBus::add_node(std::string name) {
  nodes_.push_back(Node{});
  nodes_.back().name = std::move(name);
  return nodes_.size() - 1;
}

void CanBus::set_listening(std::size_t node, bool listening) { nodes_.at(node).listening = listening; }

void CanBus::request(std::size_t node, std::int64_t time_ns, const CanFrame& frame, std::uint64_t tag) {
  Node& n = nodes_.at(node);
  check_frame(frame);
  if (time_ns < horizon_)
    throw std::logic_error("CAN request from " + n.name + " at " + std::to_string(time_ns) +
                           " ns, before the bus's decided horizon " + std::to_string(horizon_) + " ns");
  if (!n.queue.empty() && time_ns < n.queue.back().time_ns)
    throw std::logic_error("CAN requests from " + n.name + " go back in time");
  n.queue.push_back(
      Request{std::min(time_ns, kMaxTimeNs), frame, tag, arbitration_field(frame), can_bits::wire_bits(frame)});
  ++queued_;
}

void CanBus::clear(std::size_t node) {
  Node& n = nodes_.at(node);
  queued_ -= n.queue.size();
  n.queue.clear();
  n.suspended = false;
  n.failures_in_a_row = 0;
}

CanCounters CanBus::counters(std::size_t node) const {
  const Node& n = nodes_.at(node);
  CanCounters c;
  c.tec = n.tec;
  c.rec = n.rec;
  // TEC never passes 255 here: only ACK errors raise it and they stop at error passive.
  c.state = n.tec > 255                                                ? CanErrorState::bus_off
            : (n.tec >= kErrorPassiveTec || n.rec >= kErrorPassiveTec) ? CanErrorState::passive
                                                                       : CanErrorState::active;
  c.unreported_failures = n.unreported_failures;
  return c;
}

std::int64_t CanBus::after_bits(std::int64_t start_ns, std::int64_t bits) const {
  return start_ns + static_cast<std::int64_t>((static_cast<Int128>(bits) * kNsPerS + bitrate_ / 2) / bitrate_);
}

std::int64_t CanBus::time_at(std::int64_t grid_bits) const { return after_bits(anchor_ns_, grid_bits); }

void CanBus::normalise_grid() {
  // `bitrate_` bits are exactly one second, so the move loses nothing.
  const std::int64_t seconds = idle_bits_ / bitrate_;
  anchor_ns_ += seconds * kNsPerS;
  idle_bits_ -= seconds * bitrate_;
}

bool CanBus::acked_by_other(std::size_t sender) const {
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    if (i != sender && nodes_[i].listening) return true;
  return false;
}

void CanBus::report_failure(Node& n, const Request& r, std::size_t sender, std::int64_t sof_bits,
                            std::vector<CanTransfer>& done) {
  ++n.failures_in_a_row;
  if (n.failures_in_a_row > kReportedFailures) {
    ++n.unreported_failures;
    return;
  }
  const std::int64_t busy = r.wire_bits - kAfterAckSlotBits + can_bits::kErrorFrameBits;
  done.push_back(CanTransfer{time_at(sof_bits), time_at(sof_bits + busy), sender, r.frame, r.tag, false});
}

void CanBus::repeat_failures(std::size_t sender, std::int64_t sof_bits, std::int64_t t_end,
                             std::vector<CanTransfer>& done) {
  Node& n = nodes_[sender];
  const Request& r = n.queue.front();
  std::int64_t limit = t_end;
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    if (i != sender && !nodes_[i].queue.empty()) limit = std::min(limit, nodes_[i].queue.front().time_ns);
  const std::int64_t busy = r.wire_bits - kAfterAckSlotBits + can_bits::kErrorFrameBits;
  const std::int64_t period = busy + can_bits::kIntermissionBits + can_bits::kSuspendBits;
  // Attempt j starts at grid bit sof_bits + j * period; it repeats the pattern while it starts
  // before `limit` (a request ready at that very instant would contend for the bus).
  // time_at(b) < limit  <=>  b * 1e9 + rate/2 < (limit - anchor) * rate.
  const Int128 bound = static_cast<Int128>(limit - anchor_ns_) * bitrate_ - bitrate_ / 2;
  const Int128 last_bit = bound <= 0 ? -1 : (bound - 1) / kNsPerS;  // the largest b that passes
  std::int64_t repeats = last_bit < sof_bits ? 0 : static_cast<std::int64_t>((last_bit - sof_bits) / period);
  // The closed form, checked against the definition at its edge.
  while (repeats > 0 && time_at(sof_bits + repeats * period) >= limit) --repeats;
  while (time_at(sof_bits + (repeats + 1) * period) < limit) ++repeats;
  if (repeats == 0) return;

  const std::uint64_t reportable =
      n.failures_in_a_row >= kReportedFailures ? 0 : kReportedFailures - n.failures_in_a_row;
  const std::uint64_t reported = std::min<std::uint64_t>(reportable, static_cast<std::uint64_t>(repeats));
  for (std::uint64_t j = 1; j <= reported; ++j)
    report_failure(n, r, sender, sof_bits + static_cast<std::int64_t>(j) * period, done);
  const std::uint64_t skipped = static_cast<std::uint64_t>(repeats) - reported;
  n.failures_in_a_row += skipped;
  n.unreported_failures += skipped;
  idle_bits_ = sof_bits + repeats * period + busy + can_bits::kIntermissionBits;
}

void CanBus::run_until(std::int64_t t_end, std::vector<CanTransfer>& done) {
  t_end = std::min(t_end, kMaxTimeNs);
  if (t_end <= horizon_) return;
  while (queued_ > 0) {
    const std::int64_t idle = time_at(idle_bits_);
    const std::int64_t suspend_end = time_at(idle_bits_ + can_bits::kSuspendBits);
    auto ready = [&](const Node& n) { return std::max(n.queue.front().time_ns, n.suspended ? suspend_end : idle); };
    std::int64_t sof = INT64_MAX;
    for (const Node& n : nodes_)
      if (!n.queue.empty()) sof = std::min(sof, ready(n));
    if (sof >= t_end) break;

    std::size_t winner = nodes_.size();
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      const Node& n = nodes_[i];
      if (n.queue.empty() || ready(n) > sof) continue;
      if (winner == nodes_.size() || n.queue.front().arbitration < nodes_[winner].queue.front().arbitration) winner = i;
    }
    std::int64_t sof_bits = 0;
    if (sof == idle) {
      sof_bits = idle_bits_;
    } else if (sof == suspend_end) {
      sof_bits = idle_bits_ + can_bits::kSuspendBits;
    } else {  // the bus was idle: every node synchronises on this SOF
      anchor_ns_ = sof;
    }
    for (Node& n : nodes_) n.suspended = false;

    Node& n = nodes_[winner];
    const Request& r = n.queue.front();
    if (acked_by_other(winner)) {
      done.push_back(CanTransfer{sof, time_at(sof_bits + r.wire_bits), winner, r.frame, r.tag, true});
      idle_bits_ = sof_bits + r.wire_bits + can_bits::kIntermissionBits;
      if (n.tec > 0) --n.tec;
      n.suspended = n.tec >= kErrorPassiveTec;  // an error-passive sender waits after any frame
      for (std::size_t i = 0; i < nodes_.size(); ++i)
        if (i != winner && nodes_[i].listening && nodes_[i].rec > 0) --nodes_[i].rec;
      n.failures_in_a_row = 0;
      n.queue.pop_front();
      --queued_;
    } else {
      report_failure(n, r, winner, sof_bits, done);
      idle_bits_ = sof_bits + r.wire_bits - kAfterAckSlotBits + can_bits::kErrorFrameBits + can_bits::kIntermissionBits;
      // ISO 11898-1: an error-passive transmitter's ACK error leaves TEC as it is.
      if (n.tec < kErrorPassiveTec) n.tec = static_cast<std::uint16_t>(n.tec + kAckErrorTecStep);
      if (n.tec >= kErrorPassiveTec) {
        n.suspended = true;
        repeat_failures(winner, sof_bits, t_end, done);
      }
    }
    normalise_grid();
  }
  horizon_ = t_end;
}

}  // namespace sear
