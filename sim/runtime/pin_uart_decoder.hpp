// The receiver of a device wired to a soft UART's TX pin: decodes 8N1 bytes from the pin's level
// changes, as a UART receiver would from the line. A start bit is a falling edge while idle; each
// data bit and the stop bit are read at their middles counted from that edge; a low stop bit (a
// framing error) still gives its byte, as an AVR USART delivers it; the next start edge counts
// from the stop bit's middle on.
#pragma once

#include <cstdint>
#include <vector>

#include "devices/serial_byte.h"

namespace sear {

class PinUartDecoder {
 public:
  // The line idles at `idle_level` (1, or 0 for RS-232 polarity at logic levels).
  explicit PinUartDecoder(int idle_level = 1);
  // The receiver's rate from now on (the device's); a frame in progress keeps its own.
  void set_baud(std::uint32_t baud) { baud_ = baud; }
  // The line changed to `level` at t_ns; changes come in time order.
  void edge(int level, std::int64_t t_ns, std::vector<serial_byte>& out);
  // The line is known to have kept its level until known_ns: bytes whose stop bit's middle lies
  // before it are complete. Each is stamped with the end of its stop bit and the receiver's baud.
  void known_until(std::int64_t known_ns, std::vector<serial_byte>& out);
  std::uint64_t framing_errors() const { return framing_errors_; }

 private:
  std::int64_t sample_ns(int bit) const;

  int invert_;
  int level_;  // logic level since the last change
  std::uint32_t baud_ = 0;
  bool in_frame_ = false;
  std::uint32_t frame_baud_ = 0;
  std::int64_t start_ns_ = 0;
  int next_bit_ = 1;
  std::uint8_t value_ = 0;
  std::int64_t hunt_from_ns_ = INT64_MIN;
  std::uint64_t framing_errors_ = 0;
};

}  // namespace sear
