#include "scene/diagnostics.hpp"

#include <fmt/format.h>

namespace sear {

std::string Diagnostic::str() const {
  if (line > 0) return fmt::format("{}:{}: error: {}", file, line, message);
  return fmt::format("{}: error: {}", file, message);
}

void Diagnostics::error(const std::string& file, int line, std::string message) {
  items_.push_back({file, line, std::move(message)});
}

std::string Diagnostics::joined() const {
  std::string out;
  for (const auto& d : items_) out += d.str() + "\n";
  return out;
}

}  // namespace sear
