#include "scene/diagnostics.hpp"

#include <fmt/format.h>

namespace sear {

std::string Diagnostic::str() const {
  if (line > 0) return fmt::format("{}:{}: error: {}", file, line, message);
  return fmt::format("{}: error: {}", file, message);
}

void Diagnostics::error(const std::string& file, int line, std::string message) {
  ++count_;
  if (items_.size() < kMaxKept) items_.push_back({file, line, std::move(message)});
}

std::string Diagnostics::joined() const {
  std::string out;
  for (const auto& d : items_) out += d.str() + "\n";
  if (count_ > items_.size()) {
    const std::size_t more = count_ - items_.size();
    out += fmt::format("... and {} more error{}\n", more, more == 1 ? "" : "s");
  }
  return out;
}

}  // namespace sear
