// The table of device kinds (see device_kinds.hpp): the loader, `sear sensors` and the lockstep
// bridge all read it, so adding a kind never adds a branch anywhere else.
#include "devices/device_kinds.hpp"

#include <algorithm>
#include <cmath>

namespace sear {

const std::vector<const DeviceKind*>& device_kinds() {
#define SEAR_KIND_ROW(name) &name##_kind(),
  static const std::vector<const DeviceKind*> kinds = {SEAR_DEVICE_KINDS(SEAR_KIND_ROW)};
#undef SEAR_KIND_ROW
  return kinds;
}

// Worked out in doubles, capped, so that an absurd resolution is reported rather than counted.
double beam_ray_count(double half_angle, double resolution) {
  double total = 1;
  if (!(half_angle > 0)) return total;
  const double cones = std::ceil(half_angle / resolution - 1e-9);
  for (double k = 0; k < cones && total <= 1e6; ++k) {
    const double ratio = std::sin(0.5 * resolution) / std::sin(half_angle - k * resolution);
    total += ratio < 1 ? std::max(3.0, std::ceil(M_PI / std::asin(ratio) - 1e-9)) : 3.0;
  }
  return total;
}

}  // namespace sear
