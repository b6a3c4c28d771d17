// A device on a serial line, hosted in the simulator's process (a GPS talker, a LIDAR, a sonar's
// serial output): bytes in, time-stamped bytes out. It knows nothing of its other end, which may
// be an MCU's port, a host pseudo-terminal or a test.
#pragma once

#include <cstddef>
#include <cstdint>

extern "C" {
#include "devices/serial_byte.h"
}

namespace sear {

class UartDevice {
 public:
  virtual ~UartDevice() = default;
  // A byte from the other end, as the device's receiver decoded it.
  virtual void receive(const serial_byte& byte) = 0;
  // Puts into out (at most cap) every byte whose stop bit ends before until_ns, in order; none
  // starts before now_ns, which the other end has already reached. Called with non-decreasing
  // times; what cap cuts off comes at the next call.
  virtual std::size_t transmit(std::int64_t now_ns, std::int64_t until_ns, serial_byte* out, std::size_t cap) = 0;
  // The rate its receiver listens at now, and since when: a device that switches rate after its
  // last reply byte switches at that byte's end, whichever quantum the host learns it in.
  virtual std::uint32_t baud() const = 0;
  virtual std::int64_t baud_since_ns() const { return 0; }
  // True when its output has RS-232 polarity at logic levels (idle low, bits inverted) as wired.
  virtual bool inverted() const { return false; }
};

}  // namespace sear
