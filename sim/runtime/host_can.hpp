// The host's end of a simulated CAN bus (a SocketCAN interface, or a test): frames the host sent
// since the last look enter the bus then; every frame the bus carried from a simulated node goes
// out to it.
#pragma once

#include <vector>

#include "runtime/can_frame.hpp"

namespace sear {

class HostCanEnd {
 public:
  virtual ~HostCanEnd() = default;
  // Appends every frame the host sent since the last call, in order; never blocks.
  virtual std::size_t read_available(std::vector<CanFrame>& out) = 0;
  virtual void write(const CanFrame& frame) = 0;
};

}  // namespace sear
