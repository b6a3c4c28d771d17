#include "runtime/pin_uart_decoder.hpp"

namespace sear {

PinUartDecoder::PinUartDecoder(int idle_level) : invert_(idle_level ? 0 : 1) { uart_edges_init(&line_, 1); }

void PinUartDecoder::known_until(std::int64_t known_ns, std::vector<serial_byte>& out) {
  std::uint8_t value = 0;
  int stop_level = 1;
  while (uart_edges_byte_before(&line_, known_ns, &value, &stop_level)) {
    if (!stop_level) ++framing_errors_;
    out.push_back({line_.start_ns + serial_frame_ns(line_.frame_baud), line_.frame_baud, value, {}});
  }
}

void PinUartDecoder::edge(int level, std::int64_t t_ns, std::vector<serial_byte>& out) {
  known_until(t_ns, out);
  uart_edges_change(&line_, (level ? 1 : 0) ^ invert_, t_ns, baud_);
}

}  // namespace sear
