// WGS84 geodetic <-> local East-North-Up conversions, via Earth-centred Earth-fixed (ECEF) coordinates.
#include "scene/geodetic.hpp"

#include <cmath>

namespace sear {
namespace {

// WGS84 defining parameters: NIMA TR8350.2, "Department of Defense World Geodetic System 1984",
// 3rd edition, table 3.1.
constexpr double kSemiMajorAxis = 6378137.0;         // a, metres
constexpr double kFlattening = 1.0 / 298.257223563;  // f
// WGS84 derived geometric constants, computed from a and f as in TR8350.2 table 3.3 rather than
// copied as rounded literals.
constexpr double kSemiMinorAxis = kSemiMajorAxis * (1.0 - kFlattening);                  // b
constexpr double kFirstEccentricitySq = kFlattening * (2.0 - kFlattening);               // e^2
constexpr double kSecondEccentricitySq = kFirstEccentricitySq / (1.0 - kFirstEccentricitySq);  // e'^2

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
constexpr double kRadToDeg = 180.0 / kPi;

struct Ecef {
  double x, y, z;
};

Ecef geodetic_to_ecef(const GeoPoint& p) {
  const double lat = p.latitude_deg * kDegToRad;
  const double lon = p.longitude_deg * kDegToRad;
  const double sin_lat = std::sin(lat);
  const double cos_lat = std::cos(lat);
  const double prime_vertical_radius =
      kSemiMajorAxis / std::sqrt(1.0 - kFirstEccentricitySq * sin_lat * sin_lat);
  const double r = (prime_vertical_radius + p.altitude_m) * cos_lat;
  return {r * std::cos(lon), r * std::sin(lon),
          (prime_vertical_radius * (1.0 - kFirstEccentricitySq) + p.altitude_m) * sin_lat};
}

// Bowring's (1976) formula, iterated. One pass is already sub-millimetre for terrestrial heights;
// the extra passes take it to rounding level, which keeps round trips exact to well below 1 mm
// even for points far above or below the ellipsoid. Both atan2 calls stay well conditioned as the
// distance from the axis goes to zero, so latitudes arbitrarily close to the poles are fine.
GeoPoint ecef_to_geodetic(const Ecef& c) {
  const double p = std::hypot(c.x, c.y);  // distance from the polar axis
  // Start from the parametric (reduced) latitude of the point as if it were on the ellipsoid.
  double beta = std::atan2(c.z, (1.0 - kFlattening) * p);
  double lat = 0.0;
  for (int i = 0; i < 5; ++i) {
    const double sin_beta = std::sin(beta);
    const double cos_beta = std::cos(beta);
    lat = std::atan2(c.z + kSecondEccentricitySq * kSemiMinorAxis * sin_beta * sin_beta * sin_beta,
                     p - kFirstEccentricitySq * kSemiMajorAxis * cos_beta * cos_beta * cos_beta);
    const double next_beta = std::atan2((1.0 - kFlattening) * std::sin(lat), std::cos(lat));
    const bool converged = std::fabs(next_beta - beta) < 1e-15;
    beta = next_beta;
    if (converged) break;
  }
  const double sin_lat = std::sin(lat);
  const double cos_lat = std::cos(lat);
  // Height along the normal, written so that it neither divides by cos(lat) (blows up at the
  // poles) nor by sin(lat) (blows up at the equator): h = p cos(lat) + z sin(lat) - a^2 / N.
  const double altitude = p * cos_lat + c.z * sin_lat -
                          kSemiMajorAxis * std::sqrt(1.0 - kFirstEccentricitySq * sin_lat * sin_lat);
  // atan2 already returns (-180, 180], which is what wraps longitudes across the antimeridian.
  return {lat * kRadToDeg, std::atan2(c.y, c.x) * kRadToDeg, altitude};
}

}  // namespace

LocalTangentPlane::LocalTangentPlane(const GeoPoint& origin) : origin_(origin) {
  const Ecef o = geodetic_to_ecef(origin);
  origin_x_ = o.x;
  origin_y_ = o.y;
  origin_z_ = o.z;
  sin_lat_ = std::sin(origin.latitude_deg * kDegToRad);
  cos_lat_ = std::cos(origin.latitude_deg * kDegToRad);
  sin_lon_ = std::sin(origin.longitude_deg * kDegToRad);
  cos_lon_ = std::cos(origin.longitude_deg * kDegToRad);
}

Enu LocalTangentPlane::to_enu(const GeoPoint& p) const {
  const Ecef c = geodetic_to_ecef(p);
  const double dx = c.x - origin_x_;
  const double dy = c.y - origin_y_;
  const double dz = c.z - origin_z_;
  const double along_meridian_plane = cos_lon_ * dx + sin_lon_ * dy;
  return {-sin_lon_ * dx + cos_lon_ * dy,
          -sin_lat_ * along_meridian_plane + cos_lat_ * dz,
          cos_lat_ * along_meridian_plane + sin_lat_ * dz};
}

GeoPoint LocalTangentPlane::to_geo(const Enu& e) const {
  // The ENU axes are orthonormal, so the inverse rotation is the transpose.
  const double along_meridian_plane = -sin_lat_ * e.north_m + cos_lat_ * e.up_m;
  const Ecef c{origin_x_ - sin_lon_ * e.east_m + cos_lon_ * along_meridian_plane,
               origin_y_ + cos_lon_ * e.east_m + sin_lon_ * along_meridian_plane,
               origin_z_ + cos_lat_ * e.north_m + sin_lat_ * e.up_m};
  return ecef_to_geodetic(c);
}

const GeoPoint& LocalTangentPlane::origin() const { return origin_; }

}  // namespace sear
