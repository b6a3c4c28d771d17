// The parameters and checks every beam-shaped ranger shares (infrared and ultrasonic), so that
// each kind's row lists them the same way and builds its RangeBeam from them alike.
#pragma once

#include "scene/description.hpp"
#include "scene/device_kind.hpp"
#include "sensors/range_sensor.hpp"

namespace sear {

// half_angle_deg, resolution_deg and max_range, with these defaults.
std::vector<DeviceParam> beam_params(double half_angle_deg, double resolution_deg, double max_range_m);
// The same and max_incidence_deg: a surface struck more obliquely than this returns no echo.
std::vector<DeviceParam> sonar_params(double half_angle_deg, double resolution_deg, double max_range_m,
                                      double max_incidence_deg);
// The beam of a device whose row has beam_params() (and sonar_params()), on its mount.
RangeBeam beam_of(const DeviceDesc& d);
// Refuses a beam with more rays than RangeSensor takes; for DeviceKind::check.
void check_beam(const DeviceDesc& d, ElementReader& r);

}  // namespace sear
