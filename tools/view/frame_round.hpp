// Rounding for the viewer's messages (tools/view/PROTOCOL.md): what a picture needs and no more,
// so that frames and replay files stay small; and the vectors, quaternions and times built from it.
#pragma once

#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>

namespace sear {

// Positions and lengths to 1 mm.
inline double round_mm(double v) { return std::round(v * 1e3) / 1e3; }
// Angles, quaternion components, unit vectors to 1e-4.
inline double round_unit(double v) { return std::round(v * 1e4) / 1e4; }
// Any other quantity (volts, tesla, register values in SI) to 6 significant digits.
inline double round_sig(double v) {
  if (v == 0 || !std::isfinite(v)) return v;
  const double scale = std::pow(10.0, 5 - std::floor(std::log10(std::fabs(v))));
  return std::round(v * scale) / scale;
}
// A time in seconds to 1 us.
inline double round_seconds(std::int64_t t_ns) { return std::round(static_cast<double>(t_ns) * 1e-3) * 1e-6; }

// [x, y, z] in metres to 1 mm.
inline nlohmann::ordered_json vec3(double x, double y, double z) {
  return nlohmann::ordered_json::array({round_mm(x), round_mm(y), round_mm(z)});
}
inline nlohmann::ordered_json vec3(const double* p) { return vec3(p[0], p[1], p[2]); }
// [w, x, y, z] (ODE's order) to 1e-4.
inline nlohmann::ordered_json quat(double w, double x, double y, double z) {
  return nlohmann::ordered_json::array({round_unit(w), round_unit(x), round_unit(y), round_unit(z)});
}
inline nlohmann::ordered_json quat(const double* q) { return quat(q[0], q[1], q[2], q[3]); }

}  // namespace sear
