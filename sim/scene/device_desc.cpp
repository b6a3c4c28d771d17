// Looking up a device's wiring and parameters by attribute name, and a kind by its element.
#include <cstring>
#include <stdexcept>

#include "scene/description.hpp"
#include "scene/device_kind.hpp"

namespace sear {
namespace {

template <typename Row>
std::size_t index_of(const std::vector<Row>& rows, const char* attribute, const DeviceKind* kind) {
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (std::strcmp(rows[i].attribute, attribute) == 0) return i;
  throw std::out_of_range(std::string("device kind <") + (kind ? kind->element : "?") + "> has no '" + attribute + "'");
}

}  // namespace

int DeviceDesc::wire(const char* attribute) const { return wires.at(index_of(kind->wires, attribute, kind)); }
double DeviceDesc::value(const char* attribute) const { return values.at(index_of(kind->params, attribute, kind)); }
const std::string& DeviceDesc::text(const char* attribute) const {
  return texts.at(index_of(kind->params, attribute, kind));
}

const DeviceKind* find_device_kind(const std::string& element) {
  for (const DeviceKind* k : device_kinds())
    if (element == k->element) return k;
  return nullptr;
}

}  // namespace sear
