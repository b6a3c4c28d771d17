#include "runtime/pin_uart_decoder.hpp"

namespace sear {

PinUartDecoder::PinUartDecoder(int idle_level) : invert_(idle_level ? 0 : 1), level_(1) {}

// Middle of bit j (0 start, 1..8 data, 9 stop), from the start edge, to the nearest ns.
std::int64_t PinUartDecoder::sample_ns(int bit) const {
  const auto baud = static_cast<std::int64_t>(frame_baud_);
  return start_ns_ + ((2 * bit + 1) * std::int64_t{1000000000} + baud) / (2 * baud);
}

void PinUartDecoder::known_until(std::int64_t known_ns, std::vector<serial_byte>& out) {
  while (in_frame_ && sample_ns(next_bit_) < known_ns) {
    if (next_bit_ <= 8) {
      value_ = static_cast<std::uint8_t>(value_ | level_ << (next_bit_ - 1));
      ++next_bit_;
      continue;
    }
    if (!level_) ++framing_errors_;
    hunt_from_ns_ = sample_ns(9);
    in_frame_ = false;
    out.push_back({start_ns_ + serial_frame_ns(frame_baud_), frame_baud_, value_, {}});
  }
}

void PinUartDecoder::edge(int level, std::int64_t t_ns, std::vector<serial_byte>& out) {
  known_until(t_ns, out);
  level_ = (level ? 1 : 0) ^ invert_;
  if (!in_frame_ && level_ == 0 && baud_ && t_ns >= hunt_from_ns_) {
    in_frame_ = true;
    frame_baud_ = baud_;
    start_ns_ = t_ns;
    next_bit_ = 1;
    value_ = 0;
  }
}

}  // namespace sear
