// World ENU -> WGS-84 fix through the exact tangent plane, and the rotation of velocities into the
// antenna's own east-north-up frame.
#include "sensors/gnss_truth.hpp"

#include <cmath>
#include <utility>

namespace sear {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

// Rows: east, north, up unit vectors in ECEF at a latitude and longitude.
struct EnuAxes {
  double e[3], n[3], u[3];
};

EnuAxes axes_at(double latitude_deg, double longitude_deg) {
  const double sl = std::sin(latitude_deg * kDegToRad), cl = std::cos(latitude_deg * kDegToRad);
  const double so = std::sin(longitude_deg * kDegToRad), co = std::cos(longitude_deg * kDegToRad);
  return {{-so, co, 0.0}, {-sl * co, -sl * so, cl}, {cl * co, cl * so, sl}};
}

}  // namespace

GnssTruth::GnssTruth(const GeoPoint& origin, double geoid_separation_m)
    : plane_(origin), geoid_separation_m_(geoid_separation_m) {}

Enu GnssTruth::local_velocity(const Enu& position, const Enu& velocity) const {
  const GeoPoint p = plane_.to_geo(position);
  const EnuAxes o = axes_at(plane_.origin().latitude_deg, plane_.origin().longitude_deg);
  const EnuAxes a = axes_at(p.latitude_deg, p.longitude_deg);
  double ecef[3];
  for (int i = 0; i < 3; ++i)
    ecef[i] = o.e[i] * velocity.east_m + o.n[i] * velocity.north_m + o.u[i] * velocity.up_m;
  auto dot = [&ecef](const double* axis) { return axis[0] * ecef[0] + axis[1] * ecef[1] + axis[2] * ecef[2]; };
  return {dot(a.e), dot(a.n), dot(a.u)};
}

gnss_fix_truth GnssTruth::at(std::int64_t time_ns, const Enu& position, const Enu& velocity) const {
  const GeoPoint p = plane_.to_geo(position);
  const Enu v = local_velocity(position, velocity);
  gnss_fix_truth t{};
  t.time_ns = time_ns;
  t.latitude_deg = p.latitude_deg;
  t.longitude_deg = p.longitude_deg;
  t.altitude_msl_m = p.altitude_m - geoid_separation_m_;
  t.geoid_separation_m = geoid_separation_m_;
  t.east_mps = v.east_m;
  t.north_mps = v.north_m;
  t.up_mps = v.up_m;
  return t;
}

double speed_over_ground_mps(const gnss_fix_truth& t) { return std::hypot(t.east_mps, t.north_mps); }

double course_over_ground_deg(const gnss_fix_truth& t) {
  double c = std::atan2(t.east_mps, t.north_mps) / kDegToRad;
  if (c < 0.0) c += 360.0;
  return c >= 360.0 ? 0.0 : c;
}

void GnssTruthFeed::call(void* context, std::int64_t time_ns, gnss_fix_truth* out) {
  auto* self = static_cast<GnssTruthFeed*>(context);
  Enu position{0.0, 0.0, 0.0}, velocity{0.0, 0.0, 0.0};
  self->state_(time_ns, position, velocity);
  *out = self->truth_.at(time_ns, position, velocity);
}

}  // namespace sear
