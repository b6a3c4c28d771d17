#include "expect/expectation.hpp"

#include <fmt/format.h>

namespace sear {
namespace {

// Times as written in files: "50", "2.5" (fmt's shortest form of the double). Divided, not
// multiplied by 1e-9, which is inexact: 30 s would print as 30.000000000000004.
std::string plain_seconds(std::int64_t ns) { return fmt::format("{} s", static_cast<double>(ns) / 1e9); }

std::string before_text(const Expectation& e) {
  return e.before_ns ? " before " + plain_seconds(*e.before_ns) : "";
}

std::string hex_text(const std::string& bytes) {
  std::string out;
  for (unsigned char b : bytes) out += fmt::format("{}{:02X}", out.empty() ? "" : " ", b);
  return out;
}

struct Describe {
  const Expectation& e;
  std::string operator()(const ConsoleExpect& c) const {
    if (c.never) return fmt::format("console {} never \"{}\"", e.mcu, c.pattern);
    return fmt::format("console {} matches \"{}\"{}", e.mcu, c.pattern, before_text(e));
  }
  std::string operator()(const RegionExpect& r) const {
    if (r.shape == RegionExpect::Shape::Circle)
      return fmt::format("region {} circle ({}, {}) r {}{}", e.robot, r.center_m.x(), r.center_m.y(), r.radius_m,
                         before_text(e));
    return fmt::format("region {} box ({}, {})..({}, {}){}", e.robot, r.min_m.x(), r.min_m.y(), r.max_m.x(),
                       r.max_m.y(), before_text(e));
  }
  std::string operator()(const CollisionExpect& c) const {
    return c.with.empty() ? fmt::format("no collision {}", e.robot) : fmt::format("no collision {} with {}", e.robot, c.with);
  }
  std::string operator()(const PinExpect& p) const {
    if (p.from_ns == p.to_ns) return fmt::format("pin {} {} is {} at {}", e.mcu, p.pin, p.level, plain_seconds(p.from_ns));
    return fmt::format("pin {} {} is {} from {} to {}", e.mcu, p.pin, p.level, plain_seconds(p.from_ns),
                       plain_seconds(p.to_ns));
  }
  std::string operator()(const UartExpect& u) const {
    const std::string what = u.at_least ? fmt::format("at least {} bytes", u.at_least)
                             : u.hex    ? "contains " + hex_text(u.pattern)
                                        : fmt::format("contains \"{}\"", u.pattern);
    return fmt::format("uart {} port {} {} {}{}", e.mcu, u.port, u.tx ? "tx" : "rx", what, before_text(e));
  }
  std::string operator()(const RunningExpect&) const { return fmt::format("mcu {} keeps running", e.mcu); }
};

}  // namespace

std::string describe(const Expectation& e) { return std::visit(Describe{e}, e.what); }

std::string seconds_text(std::int64_t ns) {
  // Milliseconds, rounded half up by integer arithmetic: a double would print 2.4995 s as 2.499.
  const std::int64_t ms = (ns + 500000) / 1000000;
  return fmt::format("{}.{:03d} s", ms / 1000, ms % 1000);
}

}  // namespace sear
