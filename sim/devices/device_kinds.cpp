// The table of device kinds (see device_kinds.hpp): the loader, `sear sensors` and the lockstep
// bridge all read it, so adding a kind never adds a branch anywhere else.
#include "devices/device_kinds.hpp"

namespace sear {

const std::vector<const DeviceKind*>& device_kinds() {
#define SEAR_KIND_ROW(name) &name##_kind(),
  static const std::vector<const DeviceKind*> kinds = {SEAR_DEVICE_KINDS(SEAR_KIND_ROW)};
#undef SEAR_KIND_ROW
  return kinds;
}

}  // namespace sear
