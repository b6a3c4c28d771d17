#include "scene/diagnostics.hpp"

#include <fmt/format.h>

namespace sear {

std::string Diagnostic::str() const {
  const char* kind = warning ? "warning" : "error";
  if (line > 0) return fmt::format("{}:{}: {}: {}", file, line, kind, message);
  return fmt::format("{}: {}: {}", file, kind, message);
}

void Diagnostics::warning(const std::string& file, int line, std::string message) {
  if (warnings_.size() < kMaxKept) warnings_.push_back({file, line, std::move(message), true});
}

std::string Diagnostics::warnings_joined() const {
  std::string out;
  for (const auto& d : warnings_) out += d.str() + "\n";
  return out;
}

void Diagnostics::error(const std::string& file, int line, std::string message) {
  ++count_;
  if (items_.size() < kMaxKept) items_.push_back({file, line, std::move(message), false});
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
