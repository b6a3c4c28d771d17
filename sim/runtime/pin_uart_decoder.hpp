// The receiver of a device wired to a soft UART's TX pin: decodes 8N1 bytes from the pin's level
// changes, as a UART receiver would from the line (devices/uart_edges.h reads the bits); a low
// stop bit (a framing error) still gives its byte, as an AVR USART delivers it.
#pragma once

#include <cstdint>
#include <vector>

#include "devices/serial_byte.h"
#include "devices/uart_edges.h"

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
  int invert_;
  std::uint32_t baud_ = 0;
  uart_edges line_;
  std::uint64_t framing_errors_ = 0;
};

}  // namespace sear
