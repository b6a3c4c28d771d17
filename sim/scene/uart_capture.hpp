// Reads the bytes of a SEAR UART capture (ROBOT.MCU.uartN.log, see docs/outputs.md) so that a port can
// receive what another device once sent: each `tx` line becomes a byte due at its time.
#pragma once

#include <string>
#include <vector>

#include "scene/description.hpp"
#include "scene/diagnostics.hpp"

namespace sear {

// The capture's `tx` bytes in time order; `rx` and `baud` lines and `#` comments are skipped.
// Problems are reported against `path` and the line they are on.
std::vector<TimedByte> read_uart_capture(const std::string& path, Diagnostics& diagnostics);

}  // namespace sear
