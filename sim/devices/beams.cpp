// Beam parameters shared by the rangers' rows (see beams.hpp).
#include "devices/beams.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "scene/value_ranges.hpp"

namespace sear {
namespace {

bool has_param(const DeviceDesc& d, const char* attribute) {
  return std::any_of(d.kind->params.begin(), d.kind->params.end(),
                     [&](const DeviceParam& p) { return std::string(p.attribute) == attribute; });
}

}  // namespace

std::vector<DeviceParam> beam_params(double half_angle_deg, double resolution_deg, double max_range_m) {
  using T = DeviceParam::Type;
  return {
      {"half_angle_deg", T::Number, half_angle_deg, ranges::kHalfAngle, "deg", "half-width of the beam", {}, kDegToRad},
      {"resolution_deg", T::Number, resolution_deg, ranges::kResolution, "deg", "rays at most this far apart", {},
       kDegToRad},
      {"max_range", T::Number, max_range_m, ranges::kMaxRange, "m", "length of the rays; nothing beyond is seen"},
  };
}

std::vector<DeviceParam> sonar_params(double half_angle_deg, double resolution_deg, double max_range_m,
                                      double max_incidence_deg) {
  std::vector<DeviceParam> params = beam_params(half_angle_deg, resolution_deg, max_range_m);
  params.push_back({"max_incidence_deg", DeviceParam::Type::Number, max_incidence_deg, ranges::kIncidence, "deg",
                    "a surface struck more obliquely than this (from its normal) sends no echo back",
                    {},
                    kDegToRad});
  return params;
}

RangeBeam beam_of(const DeviceDesc& d) {
  RangeBeam b;
  b.position_m = d.position_m;
  b.yaw_rad = d.yaw_rad;
  b.pitch_rad = d.pitch_rad;
  b.half_angle_rad = d.value("half_angle_deg");
  b.resolution_rad = d.value("resolution_deg");
  b.max_range_m = d.value("max_range");
  if (has_param(d, "max_incidence_deg")) b.max_incidence_rad = d.value("max_incidence_deg");
  return b;
}

void check_beam(const DeviceDesc& d, ElementReader& r) {
  const double rays = RangeSensor::ray_count(d.value("half_angle_deg"), d.value("resolution_deg"));
  if (rays > static_cast<double>(RangeSensor::kMaxRays))
    r.error(fmt::format("<{}> half_angle_deg {:g} with resolution_deg {:g} needs {} rays per measurement; at most {} "
                        "(use a coarser resolution_deg)",
                        r.name(), d.value("half_angle_deg") / kDegToRad, d.value("resolution_deg") / kDegToRad,
                        rays > 1e6 ? std::string("over 1000000") : fmt::format("{:.0f}", rays), RangeSensor::kMaxRays));
}

}  // namespace sear
