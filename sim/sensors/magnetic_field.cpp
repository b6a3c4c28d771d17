// WMM2025 synthesis by the equations of the WMM technical report (NOAA NCEI / BGS, "The US/UK
// World Magnetic Model for 2025-2030", section 1.2): geodetic to geocentric coordinates, Schmidt
// semi-normalised associated Legendre functions by recursion, the potential's gradient, and the
// rotation back to the ellipsoid's north-east-down.
#include "sensors/magnetic_field.hpp"

#include <algorithm>
#include <cmath>

namespace sear {

namespace {

// WMM.COF rows: degree n, order m, g and h (nT) at 2025.0, and their rates (nT per year).
struct GaussCoefficient {
  int n, m;
  double g, h, g_dot, h_dot;
};

constexpr GaussCoefficient kWmm2025[] = {
    {1, 0, -29351.8, 0.0, 12.0, 0.0},     {1, 1, -1410.8, 4545.4, 9.7, -21.5},
    {2, 0, -2556.6, 0.0, -11.6, 0.0},     {2, 1, 2951.1, -3133.6, -5.2, -27.7},
    {2, 2, 1649.3, -815.1, -8.0, -12.1},  {3, 0, 1361.0, 0.0, -1.3, 0.0},
    {3, 1, -2404.1, -56.6, -4.2, 4.0},    {3, 2, 1243.8, 237.5, 0.4, -0.3},
    {3, 3, 453.6, -549.5, -15.6, -4.1},   {4, 0, 895.0, 0.0, -1.6, 0.0},
    {4, 1, 799.5, 278.6, -2.4, -1.1},     {4, 2, 55.7, -133.9, -6.0, 4.1},
    {4, 3, -281.1, 212.0, 5.6, 1.6},      {4, 4, 12.1, -375.6, -7.0, -4.4},
    {5, 0, -233.2, 0.0, 0.6, 0.0},        {5, 1, 368.9, 45.4, 1.4, -0.5},
    {5, 2, 187.2, 220.2, 0.0, 2.2},       {5, 3, -138.7, -122.9, 0.6, 0.4},
    {5, 4, -142.0, 43.0, 2.2, 1.7},       {5, 5, 20.9, 106.1, 0.9, 1.9},
    {6, 0, 64.4, 0.0, -0.2, 0.0},         {6, 1, 63.8, -18.4, -0.4, 0.3},
    {6, 2, 76.9, 16.8, 0.9, -1.6},        {6, 3, -115.7, 48.8, 1.2, -0.4},
    {6, 4, -40.9, -59.8, -0.9, 0.9},      {6, 5, 14.9, 10.9, 0.3, 0.7},
    {6, 6, -60.7, 72.7, 0.9, 0.9},        {7, 0, 79.5, 0.0, -0.0, 0.0},
    {7, 1, -77.0, -48.9, -0.1, 0.6},      {7, 2, -8.8, -14.4, -0.1, 0.5},
    {7, 3, 59.3, -1.0, 0.5, -0.8},        {7, 4, 15.8, 23.4, -0.1, 0.0},
    {7, 5, 2.5, -7.4, -0.8, -1.0},        {7, 6, -11.1, -25.1, -0.8, 0.6},
    {7, 7, 14.2, -2.3, 0.8, -0.2},        {8, 0, 23.2, 0.0, -0.1, 0.0},
    {8, 1, 10.8, 7.1, 0.2, -0.2},         {8, 2, -17.5, -12.6, 0.0, 0.5},
    {8, 3, 2.0, 11.4, 0.5, -0.4},         {8, 4, -21.7, -9.7, -0.1, 0.4},
    {8, 5, 16.9, 12.7, 0.3, -0.5},        {8, 6, 15.0, 0.7, 0.2, -0.6},
    {8, 7, -16.8, -5.2, -0.0, 0.3},       {8, 8, 0.9, 3.9, 0.2, 0.2},
    {9, 0, 4.6, 0.0, -0.0, 0.0},          {9, 1, 7.8, -24.8, -0.1, -0.3},
    {9, 2, 3.0, 12.2, 0.1, 0.3},          {9, 3, -0.2, 8.3, 0.3, -0.3},
    {9, 4, -2.5, -3.3, -0.3, 0.3},        {9, 5, -13.1, -5.2, 0.0, 0.2},
    {9, 6, 2.4, 7.2, 0.3, -0.1},          {9, 7, 8.6, -0.6, -0.1, -0.2},
    {9, 8, -8.7, 0.8, 0.1, 0.4},          {9, 9, -12.9, 10.0, -0.1, 0.1},
    {10, 0, -1.3, 0.0, 0.1, 0.0},         {10, 1, -6.4, 3.3, 0.0, 0.0},
    {10, 2, 0.2, 0.0, 0.1, -0.0},         {10, 3, 2.0, 2.4, 0.1, -0.2},
    {10, 4, -1.0, 5.3, -0.0, 0.1},        {10, 5, -0.6, -9.1, -0.3, -0.1},
    {10, 6, -0.9, 0.4, 0.0, 0.1},         {10, 7, 1.5, -4.2, -0.1, 0.0},
    {10, 8, 0.9, -3.8, -0.1, -0.1},       {10, 9, -2.7, 0.9, -0.0, 0.2},
    {10, 10, -3.9, -9.1, -0.0, -0.0},     {11, 0, 2.9, 0.0, 0.0, 0.0},
    {11, 1, -1.5, 0.0, -0.0, -0.0},       {11, 2, -2.5, 2.9, 0.0, 0.1},
    {11, 3, 2.4, -0.6, 0.0, -0.0},        {11, 4, -0.6, 0.2, 0.0, 0.1},
    {11, 5, -0.1, 0.5, -0.1, -0.0},       {11, 6, -0.6, -0.3, 0.0, -0.0},
    {11, 7, -0.1, -1.2, -0.0, 0.1},       {11, 8, 1.1, -1.7, -0.1, -0.0},
    {11, 9, -1.0, -2.9, -0.1, 0.0},       {11, 10, -0.2, -1.8, -0.1, 0.0},
    {11, 11, 2.6, -2.3, -0.1, 0.0},       {12, 0, -2.0, 0.0, 0.0, 0.0},
    {12, 1, -0.2, -1.3, 0.0, -0.0},       {12, 2, 0.3, 0.7, -0.0, 0.0},
    {12, 3, 1.2, 1.0, -0.0, -0.1},        {12, 4, -1.3, -1.4, -0.0, 0.1},
    {12, 5, 0.6, -0.0, -0.0, -0.0},       {12, 6, 0.6, 0.6, 0.1, -0.0},
    {12, 7, 0.5, -0.1, -0.0, -0.0},       {12, 8, -0.1, 0.8, 0.0, 0.0},
    {12, 9, -0.4, 0.1, 0.0, -0.0},        {12, 10, -0.2, -1.0, -0.1, -0.0},
    {12, 11, -1.3, 0.1, -0.0, 0.0},       {12, 12, -0.7, 0.2, -0.1, -0.1},
};
constexpr int kDegree = 12;
constexpr double kReferenceRadius_m = 6371200.0;  // the model's geomagnetic reference radius
constexpr double kWgs84A_m = 6378137.0;
constexpr double kWgs84F = 1.0 / 298.257223563;
constexpr double kPi = 3.14159265358979323846;

}  // namespace

Eigen::Vector3d wmm2025_ned_T(const GeoPoint& point, double decimal_year) {
  const double lat = point.latitude_deg * kPi / 180.0;
  const double lon = point.longitude_deg * kPi / 180.0;
  // Geocentric radius and latitude of the point (report eq. 7-8).
  const double e2 = kWgs84F * (2.0 - kWgs84F);
  const double sin_lat = std::sin(lat), cos_lat = std::cos(lat);
  const double rc = kWgs84A_m / std::sqrt(1.0 - e2 * sin_lat * sin_lat);
  const double p = (rc + point.altitude_m) * cos_lat;
  const double z = (rc * (1.0 - e2) + point.altitude_m) * sin_lat;
  const double r = std::hypot(p, z);
  const double phi_c = std::asin(z / r);
  const double cos_theta = std::sin(phi_c);  // theta: geocentric colatitude
  // A hair off the pole, where east has no meaning and the east sum divides by zero.
  const double sin_theta = std::max(std::cos(phi_c), 1e-12);

  const double dt = decimal_year - kWmm2025Epoch;
  double g[kDegree + 1][kDegree + 1] = {}, h[kDegree + 1][kDegree + 1] = {};
  for (const GaussCoefficient& c : kWmm2025) {
    g[c.n][c.m] = c.g + dt * c.g_dot;
    h[c.n][c.m] = c.h + dt * c.h_dot;
  }

  // Schmidt semi-normalised P_n^m(cos theta) and dP/dtheta: the unnormalised (Gauss) recursion,
  // then scaled by S_nm = sqrt((2 - delta_m0) (n - m)! / (n + m)!) built up term by term.
  double pnm[kDegree + 1][kDegree + 1] = {}, dpnm[kDegree + 1][kDegree + 1] = {};
  double schmidt[kDegree + 1][kDegree + 1] = {};
  pnm[0][0] = 1.0;
  schmidt[0][0] = 1.0;
  for (int n = 1; n <= kDegree; ++n) {
    for (int m = 0; m <= n; ++m) {
      if (m == n) {
        pnm[n][n] = sin_theta * pnm[n - 1][n - 1];
        dpnm[n][n] = sin_theta * dpnm[n - 1][n - 1] + cos_theta * pnm[n - 1][n - 1];
      } else {
        const double k = n > 1 ? double((n - 1) * (n - 1) - m * m) / double((2 * n - 1) * (2 * n - 3)) : 0.0;
        const double p2 = n > 1 ? pnm[n - 2][m] : 0.0, dp2 = n > 1 ? dpnm[n - 2][m] : 0.0;
        pnm[n][m] = cos_theta * pnm[n - 1][m] - k * p2;
        dpnm[n][m] = cos_theta * dpnm[n - 1][m] - sin_theta * pnm[n - 1][m] - k * dp2;
      }
    }
    schmidt[n][0] = schmidt[n - 1][0] * double(2 * n - 1) / double(n);
    for (int m = 1; m <= n; ++m)
      schmidt[n][m] = schmidt[n][m - 1] * std::sqrt(double((n - m + 1) * (m == 1 ? 2 : 1)) / double(n + m));
  }

  // Field components in the geocentric frame (report eq. 10-12).
  double x = 0, y = 0, zc = 0;
  const double ratio = kReferenceRadius_m / r;
  double power = ratio * ratio;
  for (int n = 1; n <= kDegree; ++n) {
    power *= ratio;  // (a / r)^(n + 2)
    for (int m = 0; m <= n; ++m) {
      const double cm = std::cos(m * lon), sm = std::sin(m * lon);
      const double gs = schmidt[n][m] * g[n][m], hs = schmidt[n][m] * h[n][m];
      const double along = gs * cm + hs * sm;
      x += power * along * dpnm[n][m];  // north = -B_theta = (1/r) dV/dtheta
      y += power * m * (gs * sm - hs * cm) * pnm[n][m];
      zc -= (n + 1) * power * along * pnm[n][m];
    }
  }
  y /= sin_theta;
  // Back to the ellipsoid's north and down (report eq. 17).
  const double psi = phi_c - lat;
  const double north = x * std::cos(psi) - zc * std::sin(psi);
  const double down = x * std::sin(psi) + zc * std::cos(psi);
  return Eigen::Vector3d(north, y, down) * 1e-9;
}

GeomagneticElements wmm2025_elements(const GeoPoint& point, double decimal_year) {
  const Eigen::Vector3d ned = wmm2025_ned_T(point, decimal_year);
  const double horizontal = std::hypot(ned.x(), ned.y());
  GeomagneticElements e;
  e.declination_rad = std::atan2(ned.y(), ned.x());
  e.inclination_rad = std::atan2(ned.z(), horizontal);
  e.intensity_T = ned.norm();
  return e;
}

Eigen::Vector3d field_enu_T(const GeomagneticElements& e) {
  const double horizontal = e.intensity_T * std::cos(e.inclination_rad);
  return {horizontal * std::sin(e.declination_rad), horizontal * std::cos(e.declination_rad),
          -e.intensity_T * std::sin(e.inclination_rad)};
}

Eigen::Vector3d field_in_sensor_T(const Eigen::Vector3d& field_enu, const Eigen::Matrix3d& world_from_sensor) {
  return world_from_sensor.transpose() * field_enu;
}

}  // namespace sear
