// What one MCU's firmware did with its pins, ports and buses over a run, gathered for the wiring
// report (runtime/wiring_report.hpp): from its events, and from the link's usage block where its
// engine keeps one.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "lockstep_link.h"

namespace sear {

struct McuUsage {
  std::array<bool, SEAR_LINK_PINS> made_output{};    // pin_mode(pin, OUTPUT), or the chip's DDR bit
  std::array<std::uint8_t, SEAR_LINK_PINS> levels{};  // levels driven as an output: bit 0 LOW, bit 1 HIGH
  std::array<bool, SEAR_LINK_PINS> waveform{};        // PWM or servo pulses
  std::array<bool, SEAR_LINK_UARTS> uart_begun{};
  sear_link_usage link{};  // the link's block as of the MCU's last turn; link.usage_kept 0: none kept
  // The end of the turn in which its stdout was first seen written: looked at after the first turn,
  // then after the first turn of each 10 ms of sim time.
  std::optional<std::int64_t> stdout_ns;
};

}  // namespace sear
