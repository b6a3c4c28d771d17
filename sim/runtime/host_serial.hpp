// The other end of a UART device when it is not an MCU's port: a program on the host (through a
// pseudo-terminal), or a test. The device and the line model stay in the simulator; this end
// only moves bytes and says at what rate the host's side of the line runs.
#pragma once

#include <cstddef>
#include <cstdint>

#include "devices/serial_byte.h"

namespace sear {

class HostSerialEnd {
 public:
  virtual ~HostSerialEnd() = default;
  // The baud rate the host's side is set to now (a pty: what the host program set with termios).
  virtual std::uint32_t baud() = 0;
  // Bytes the host wrote since the last call, at most `capacity`; never blocks.
  virtual std::size_t read(std::uint8_t* out, std::size_t capacity) = 0;
  // Bytes the host's receiver decoded, in time order; never blocks (a host that reads nothing
  // loses what does not fit, as a serial port's buffer overflows).
  virtual void write(const serial_byte* bytes, std::size_t count) = 0;
};

}  // namespace sear
