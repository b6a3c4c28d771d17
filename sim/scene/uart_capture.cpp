#include "scene/uart_capture.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

namespace sear {
namespace {

// "12.000104167" -> 12000104167: read as written, so no time moves by a rounding.
bool parse_time_ns(const std::string& text, std::int64_t& ns) {
  const auto dot = text.find('.');
  const std::string whole = text.substr(0, dot);
  std::string fraction = dot == std::string::npos ? "" : text.substr(dot + 1);
  if (whole.empty() || whole.size() > 9 || fraction.size() > 9) return false;
  for (char c : whole + fraction)
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  fraction.resize(9, '0');
  ns = std::stoll(whole) * 1000000000 + std::stoll(fraction);
  return true;
}

}  // namespace

std::vector<TimedByte> read_uart_capture(const std::string& path, Diagnostics& diagnostics) {
  std::vector<TimedByte> bytes;
  std::ifstream in(path);
  if (!in) {
    diagnostics.error(path, 0, "cannot read this UART capture");
    return bytes;
  }
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();  // written on Windows
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string time, direction, value, extra;
    fields >> time >> direction >> value;
    std::int64_t ns = 0;
    const bool known = direction == "tx" || direction == "rx" || direction == "baud";
    if (!parse_time_ns(time, ns) || !known || value.empty() || (fields >> extra)) {
      diagnostics.error(path, number, "expected 'time_s direction value' (e.g. '0.001041667 tx 48'), with direction tx, rx or baud");
      continue;
    }
    if (direction != "tx") continue;
    const bool hex = !value.empty() && value.size() <= 2 &&
                     std::all_of(value.begin(), value.end(), [](char c) { return std::isxdigit(static_cast<unsigned char>(c)); });
    const unsigned byte = hex ? static_cast<unsigned>(std::stoul(value, nullptr, 16)) : 0;
    if (!hex) {
      diagnostics.error(path, number, fmt::format("'{}' is not a byte in hex (00..ff)", value));
      continue;
    }
    if (!bytes.empty() && ns < bytes.back().time_ns) {
      diagnostics.error(path, number, "tx bytes must be in time order");
      continue;
    }
    bytes.push_back({ns, static_cast<std::uint8_t>(byte)});
  }
  return bytes;
}

}  // namespace sear
