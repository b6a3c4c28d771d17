// The device kinds SEAR knows, one registration line each: its element name, which names the
// function returning its row (XML element, wiring, parameters, factory) of the table.
#pragma once

#include "scene/device_kind.hpp"

#define SEAR_DEVICE_KINDS(X) \
  X(gp2d12)                  \
  X(gp2d15)                  \
  X(bump)

namespace sear {

#define SEAR_DECLARE_KIND(name) const DeviceKind& name##_kind();
SEAR_DEVICE_KINDS(SEAR_DECLARE_KIND)
#undef SEAR_DECLARE_KIND

// The rays a beam of this half-angle and resolution casts (RangeSensor's layout), so that a kind's
// check can refuse a beam the run could not build.
double beam_ray_count(double half_angle_rad, double resolution_rad);

}  // namespace sear
