// A CAN frame as the simulator passes it between buses, controllers, bridges and logs; the bus
// gives it its times on the wire.
#pragma once

#include <array>
#include <cstdint>

namespace sear {

struct CanFrame {
  std::uint32_t id = 0;  // 11 bits, or 29 when extended
  bool extended = false;
  bool remote = false;  // RTR: no data, dlc still says how much is asked for
  std::uint8_t dlc = 0;  // 0..8
  std::array<std::uint8_t, 8> data{};

  bool operator==(const CanFrame& o) const {
    return id == o.id && extended == o.extended && remote == o.remote && dlc == o.dlc && data == o.data;
  }
};

}  // namespace sear
