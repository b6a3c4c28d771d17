// Tests for the WGS84 <-> local East-North-Up conversions against published examples and
// closed-form geometry, never against numbers produced by the code under test.
#include "scene/geodetic.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace {

using sear::Enu;
using sear::GeoPoint;
using sear::LocalTangentPlane;

// WGS84 defining parameters: NIMA TR8350.2, 3rd edition, table 3.1.
constexpr double kA = 6378137.0;
constexpr double kF = 1.0 / 298.257223563;
constexpr double kE2 = kF * (2.0 - kF);

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

constexpr double kMm = 1e-3;

// Prime vertical (nu) and meridian (rho) radii of curvature as defined in EPSG Guidance Note 7-2:
// nu = a / sqrt(1 - e² sin²φ), rho = a(1 - e²) / (1 - e² sin²φ)^(3/2).
double prime_vertical_radius(double lat_rad) {
  const double s = std::sin(lat_rad);
  return kA / std::sqrt(1.0 - kE2 * s * s);
}
double meridian_radius(double lat_rad) {
  const double s = std::sin(lat_rad);
  return kA * (1.0 - kE2) / std::pow(1.0 - kE2 * s * s, 1.5);
}

// Difference of two longitudes folded into (-180, 180], so 179.9 vs -180.1 compares equal.
double longitude_difference_deg(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d > 180.0) d -= 360.0;
  if (d <= -180.0) d += 360.0;
  return d;
}

double dms(double deg, double min, double sec) { return deg + min / 60.0 + sec / 3600.0; }

}  // namespace

TEST(Geodetic, OriginMapsToZero) {
  for (const GeoPoint origin : {GeoPoint{0.0, 0.0, 0.0}, GeoPoint{52.52, 13.405, 34.0},
                                GeoPoint{-60.0, -179.99, -20.0}, GeoPoint{89.0, 45.0, 3000.0}}) {
    const LocalTangentPlane plane(origin);
    const Enu e = plane.to_enu(origin);
    EXPECT_NEAR(e.east_m, 0.0, 1e-9);
    EXPECT_NEAR(e.north_m, 0.0, 1e-9);
    EXPECT_NEAR(e.up_m, 0.0, 1e-9);

    const GeoPoint back = plane.to_geo(Enu{0.0, 0.0, 0.0});
    EXPECT_NEAR(back.latitude_deg, origin.latitude_deg, 1e-12);
    EXPECT_NEAR(longitude_difference_deg(back.longitude_deg, origin.longitude_deg), 0.0, 1e-12);
    EXPECT_NEAR(back.altitude_m, origin.altitude_m, 1e-6);
    EXPECT_EQ(plane.origin().latitude_deg, origin.latitude_deg);
  }
}

// EPSG Guidance Note 7-2 (IOGP Publication 373-7-2), worked example for method 9837
// "Geographic/topocentric conversions", WGS 84: topocentric origin 55°00'N 5°00'E h = 200 m;
// point 53°48'33.820"N 2°07'46.380"E h = 73.0 m gives U (east) = -189013.869 m,
// V (north) = -128642.040 m, W (up) = -4220.171 m. The same vector is in the PROJ
// documentation for +proj=topocentric. Published to 1 mm, so rounding allows 0.5 mm.
TEST(Geodetic, MatchesEpsgTopocentricExample) {
  const LocalTangentPlane plane(GeoPoint{55.0, 5.0, 200.0});
  const GeoPoint point{dms(53, 48, 33.820), dms(2, 7, 46.380), 73.0};

  const Enu e = plane.to_enu(point);
  EXPECT_NEAR(e.east_m, -189013.869, kMm);
  EXPECT_NEAR(e.north_m, -128642.040, kMm);
  EXPECT_NEAR(e.up_m, -4220.171, kMm);

  // Back the other way: 1 mm of rounding in the published ENU moves the point by at most
  // ~1e-8 degree, and its height by at most ~1 mm.
  const GeoPoint back = plane.to_geo(Enu{-189013.869, -128642.040, -4220.171});
  EXPECT_NEAR(back.latitude_deg, point.latitude_deg, 2e-8);
  EXPECT_NEAR(back.longitude_deg, point.longitude_deg, 2e-8);
  EXPECT_NEAR(back.altitude_m, point.altitude_m, 1.5 * kMm);
}

// EPSG Guidance Note 7-2, worked example for method 9602 "Geographic/geocentric conversions",
// WGS 84: 53°48'33.820"N 2°07'46.380"E h = 73.0 m is X = 3771793.968 m, Y = 140253.342 m,
// Z = 5124304.349 m. With the origin at lat 0, lon 0, h 0 the ENU axes are the ECEF axes
// reordered (east = Y, north = Z, up = X) and the origin sits at X = a, so this checks the
// geodetic -> ECEF step against the published vector.
TEST(Geodetic, MatchesEpsgGeocentricExampleThroughEquatorOrigin) {
  const LocalTangentPlane plane(GeoPoint{0.0, 0.0, 0.0});
  const GeoPoint point{dms(53, 48, 33.820), dms(2, 7, 46.380), 73.0};

  const Enu e = plane.to_enu(point);
  EXPECT_NEAR(e.east_m, 140253.342, kMm);
  EXPECT_NEAR(e.north_m, 5124304.349, kMm);
  EXPECT_NEAR(e.up_m, 3771793.968 - kA, kMm);

  const GeoPoint back = plane.to_geo(Enu{140253.342, 5124304.349, 3771793.968 - kA});
  EXPECT_NEAR(back.latitude_deg, point.latitude_deg, 2e-8);
  EXPECT_NEAR(back.longitude_deg, point.longitude_deg, 2e-8);
  EXPECT_NEAR(back.altitude_m, point.altitude_m, kMm);
}

// A point 1 degree of latitude north of an origin on the equator. ENU is the straight chord,
// not the distance along the ground, so the point is *below* the horizon and "north" is shorter
// than the 1-degree meridian arc. Three independent checks:
//  - With the origin at lat 0, lon 0, north is the ECEF Z of the point, N(1°)(1 - e²) sin 1°, and
//    up is its ECEF X minus a, N(1°) cos 1° - a (EPSG GN 7-2 method 9602 formulas).
//  - The chord length sqrt(north² + up²) is tied to the meridian arc S by the chord-of-a-curve
//    expansion chord = S - S³ / (24 M²) + O(S⁵ / M⁴), M the meridian radius of curvature. The
//    dropped terms (and the 3e-6 relative change of M over the first degree) are ~1e-5 m here.
//  - S for 0..1° on WGS84 is 110574.3886 m: the integral of M(φ) from 0 to 1°, equivalently
//    a(1 - e²)[A φ - (B/2) sin 2φ + (C/4) sin 4φ - ...] (the standard series, e.g. Wikipedia
//    "Meridian arc"); it matches the 110.574 km for the first degree tabulated in Wikipedia "Latitude".
TEST(Geodetic, OneDegreeNorthOfEquator) {
  const LocalTangentPlane plane(GeoPoint{0.0, 0.0, 0.0});
  const Enu e = plane.to_enu(GeoPoint{1.0, 0.0, 0.0});

  const double n1 = prime_vertical_radius(1.0 * kDeg);
  EXPECT_NEAR(e.east_m, 0.0, kMm);
  EXPECT_NEAR(e.north_m, n1 * (1.0 - kE2) * std::sin(1.0 * kDeg), kMm);
  EXPECT_NEAR(e.up_m, n1 * std::cos(1.0 * kDeg) - kA, kMm);
  EXPECT_LT(e.up_m, -900.0);  // roughly S² / (2M): the Earth curves away under the tangent plane

  const double arc = 110574.3886;
  const double m_mid = meridian_radius(0.5 * kDeg);
  const double expected_chord = arc - arc * arc * arc / (24.0 * m_mid * m_mid);
  EXPECT_NEAR(std::hypot(e.north_m, e.up_m), expected_chord, kMm);
}

// 0.001° of longitude along the 45° parallel. Moving along a parallel is a rotation about the
// polar axis on a circle of radius R = N(45°) cos 45°, so exactly: east = R sin Δλ,
// and the inward sag R(1 - cos Δλ) splits into north = +sag·sin φ and up = -sag·cos φ.
// east is within 5e-9 m of the small-angle R Δλ = 78.847 m.
TEST(Geodetic, SmallLongitudeOffsetAt45Degrees) {
  const double lat = 45.0;
  const double lon = -73.5;
  const double dlon = 0.001 * kDeg;
  const LocalTangentPlane plane(GeoPoint{lat, lon, 0.0});
  const Enu e = plane.to_enu(GeoPoint{lat, lon + 0.001, 0.0});

  const double radius = prime_vertical_radius(lat * kDeg) * std::cos(lat * kDeg);
  EXPECT_NEAR(e.east_m, radius * dlon, kMm);
  EXPECT_NEAR(e.east_m, radius * std::sin(dlon), 1e-6);
  const double sag = radius * (1.0 - std::cos(dlon));
  EXPECT_NEAR(e.north_m, sag * std::sin(lat * kDeg), 1e-6);
  EXPECT_NEAR(e.up_m, -sag * std::cos(lat * kDeg), 1e-6);
}

// Across the antimeridian: origin on the equator at 179.9°E, point at 179.9°W, 0.2° further east.
// Same rotation-about-the-axis geometry as above with R = a.
TEST(Geodetic, WrapsAcrossAntimeridian) {
  const LocalTangentPlane plane(GeoPoint{0.0, 179.9, 0.0});
  const double dlon = 0.2 * kDeg;
  const Enu e = plane.to_enu(GeoPoint{0.0, -179.9, 0.0});
  EXPECT_NEAR(e.east_m, kA * std::sin(dlon), kMm);
  EXPECT_NEAR(e.north_m, 0.0, kMm);
  EXPECT_NEAR(e.up_m, -kA * (1.0 - std::cos(dlon)), kMm);

  const GeoPoint back = plane.to_geo(e);
  EXPECT_NEAR(back.latitude_deg, 0.0, 1e-9);
  EXPECT_NEAR(back.longitude_deg, -179.9, 1e-9);  // reported in (-180, 180], not as 180.1
  EXPECT_NEAR(back.altitude_m, 0.0, kMm);
}

// Points about 50 km from the origin in eight directions, above and below the ellipsoid, at
// southern, equatorial, mid and near-polar latitudes, including origins next to the antimeridian.
// The offsets are placed with the local radii of curvature so that they really are ~50 km away
// (at 89° that means a longitude step of ~25°).
TEST(Geodetic, RoundTripGeoToEnuToGeo) {
  const double distance = 50000.0;
  for (const double lat0 : {-60.0, 0.0, 52.0, 89.0}) {
    for (const double lon0 : {-179.9, 7.0, 179.95}) {
      const LocalTangentPlane plane(GeoPoint{lat0, lon0, 120.0});
      for (int k = 0; k < 8; ++k) {
        const double azimuth = k * 45.0 * kDeg;
        for (const double altitude : {-80.0, 0.0, 2500.0}) {
          // Longitude may leave [-180, 180] here on purpose: to_geo must still land on the same meridian.
          const GeoPoint p{lat0 + distance * std::cos(azimuth) / meridian_radius(lat0 * kDeg) / kDeg,
                     lon0 + distance * std::sin(azimuth) /
                                (prime_vertical_radius(lat0 * kDeg) * std::cos(lat0 * kDeg)) / kDeg,
                     altitude};

          const GeoPoint back = plane.to_geo(plane.to_enu(p));
          SCOPED_TRACE(testing::Message() << "origin " << lat0 << "," << lon0 << " azimuth " << k * 45
                                          << " altitude " << altitude);
          EXPECT_NEAR(back.latitude_deg, p.latitude_deg, 1e-9);
          EXPECT_NEAR(longitude_difference_deg(back.longitude_deg, p.longitude_deg), 0.0, 1e-9);
          EXPECT_GT(back.longitude_deg, -180.0);
          EXPECT_LE(back.longitude_deg, 180.0);
          EXPECT_NEAR(back.altitude_m, p.altitude_m, kMm);
        }
      }
    }
  }
}

// The other direction, out to the 100 km the frame is meant for, including straight up and down
// and points near the pole seen from 89.9°.
TEST(Geodetic, RoundTripEnuToGeoToEnu) {
  std::vector<Enu> offsets;
  for (const double r : {1.0, 1000.0, 100000.0}) {
    for (int k = 0; k < 8; ++k) {
      const double azimuth = k * 45.0 * kDeg;
      for (const double up : {-500.0, 0.0, 10000.0}) {
        offsets.push_back({r * std::sin(azimuth), r * std::cos(azimuth), up});
      }
    }
  }
  offsets.push_back({0.0, 0.0, 30000.0});
  offsets.push_back({0.0, 0.0, -3000.0});
  for (const GeoPoint origin : {GeoPoint{-60.0, 150.0, 0.0}, GeoPoint{0.0, 0.0, 0.0},
                                GeoPoint{52.0, -1.5, 400.0}, GeoPoint{89.0, 180.0, 0.0},
                                GeoPoint{89.9, -30.0, 2800.0}, GeoPoint{-89.5, 10.0, 2800.0}}) {
    const LocalTangentPlane plane(origin);
    for (const Enu& e : offsets) {
      const Enu back = plane.to_enu(plane.to_geo(e));
      SCOPED_TRACE(testing::Message() << "origin " << origin.latitude_deg << "," << origin.longitude_deg
                                      << " enu " << e.east_m << "," << e.north_m << "," << e.up_m);
      EXPECT_NEAR(back.east_m, e.east_m, kMm);
      EXPECT_NEAR(back.north_m, e.north_m, kMm);
      EXPECT_NEAR(back.up_m, e.up_m, kMm);
    }
  }
}
