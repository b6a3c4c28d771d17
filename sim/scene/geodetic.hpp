// WGS84 GPS coordinates <-> the simulator's local world frame (x east, y north, z up),
// so that GPS sensors and geo-referenced worlds agree with the physics frame.
#pragma once

namespace sear {

// Latitude/longitude in degrees; altitude is WGS84 ellipsoidal height, not height above mean sea level.
struct GeoPoint {
  double latitude_deg;
  double longitude_deg;
  double altitude_m;
};

struct Enu {
  double east_m;
  double north_m;
  double up_m;
};

// Converts between a WGS84 geodetic point and the local East-North-Up frame whose origin is `origin`.
// The frame is the exact tangent plane (no flat-earth approximation), so it stays consistent with
// GPS far from the origin; "up" drops away below the horizon with distance as the Earth curves.
// Not defined for an origin exactly at a pole, where east and north have no meaning.
class LocalTangentPlane {
 public:
  explicit LocalTangentPlane(const GeoPoint& origin);

  Enu to_enu(const GeoPoint& p) const;
  // Longitude of the result is in (-180, 180].
  GeoPoint to_geo(const Enu& e) const;

  const GeoPoint& origin() const;

 private:
  GeoPoint origin_;
  // Origin in Earth-centred, Earth-fixed coordinates and the trigonometry of its latitude and
  // longitude, cached because every conversion needs them.
  double origin_x_, origin_y_, origin_z_;
  double sin_lat_, cos_lat_, sin_lon_, cos_lon_;
};

}  // namespace sear
