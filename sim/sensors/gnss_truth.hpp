// The GPS antenna's true fix: a body's world-frame position and velocity (x east, y north, z up
// from the world's GPS origin) as WGS-84 latitude, longitude, ellipsoidal and MSL altitude, and the
// velocity in the east-north-up frame at the antenna, which is what a receiver's speed and course
// are measured in.
#pragma once

#include <cstdint>
#include <functional>
#include <utility>

#include "devices/gnss_error.h"
#include "scene/geodetic.hpp"

namespace sear {

// Geoid separation: one documented constant per origin (the caller gives N, the geoid's height
// above the ellipsoid at the origin, e.g. from EGM96), held over the whole world. Within 10 km of
// the origin the real geoid moves by centimetres to a few decimetres (its slope is rarely above
// 3e-5), so MSL altitude carries that much model error; ellipsoidal altitude, latitude and
// longitude carry none (LocalTangentPlane is exact).
class GnssTruth {
 public:
  GnssTruth(const GeoPoint& origin, double geoid_separation_m);

  // position and velocity in the world frame; time is copied into the result.
  gnss_fix_truth at(std::int64_t time_ns, const Enu& position, const Enu& velocity) const;

  // The world-frame velocity turned into the east-north-up frame at `position`: the two frames
  // differ by the angle the Earth curves between the origin and there (1.6 mrad at 10 km).
  Enu local_velocity(const Enu& position, const Enu& velocity) const;

  const LocalTangentPlane& plane() const { return plane_; }
  double geoid_separation_m() const { return geoid_separation_m_; }

 private:
  LocalTangentPlane plane_;
  double geoid_separation_m_;
};

// Horizontal speed (m/s) and course over ground (degrees clockwise from true north, [0, 360)).
double speed_over_ground_mps(const gnss_fix_truth& t);
double course_over_ground_deg(const gnss_fix_truth& t);

// Feeds a talker: asks `state` for the antenna's world-frame position and velocity at a time.
// Must outlive the talker it was given to (the talker keeps a pointer to it).
class GnssTruthFeed {
 public:
  using State = std::function<void(std::int64_t time_ns, Enu& position, Enu& velocity)>;
  GnssTruthFeed(const GnssTruth& truth, State state) : truth_(truth), state_(std::move(state)) {}
  gnss_truth_source source() { return {&GnssTruthFeed::call, this}; }

 private:
  static void call(void* context, std::int64_t time_ns, gnss_fix_truth* out);
  GnssTruth truth_;
  State state_;
};

}  // namespace sear
