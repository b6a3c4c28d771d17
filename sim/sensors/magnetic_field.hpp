// The Earth's magnetic field a compass sees: the World Magnetic Model 2025 main field (degree and
// order 12) at the world's GPS origin, or declination, inclination and intensity given by hand,
// turned into a vector in the world frame (x east, y north, z up) and into a sensor's own axes.
#pragma once

#include <Eigen/Core>

#include "scene/geodetic.hpp"

namespace sear {

// The three numbers a geomagnetic chart gives for a place.
struct GeomagneticElements {
  double declination_rad = 0;  // magnetic north east of true north is positive
  double inclination_rad = 0;  // the field dips below the horizon by this much (positive: down, north)
  double intensity_T = 0;      // total field F
};

constexpr double kWmm2025Epoch = 2025.0;       // decimal year of the coefficients
constexpr double kWmm2025ValidUntil = 2030.0;  // the model's declared life

// WMM2025 (NOAA NCEI and BGS, public domain; coefficients of WMM.COF dated 11/13/2024) at a WGS84
// point and decimal year: north, east and down components in tesla. The main field only: crustal
// anomalies and the external field, which the WMM report puts at about 0.4-0.5 degrees of
// declination and ~150 nT globally (1 sd), are not in it. Years outside the model's life are
// extrapolated with its secular variation all the same.
Eigen::Vector3d wmm2025_ned_T(const GeoPoint& point, double decimal_year);
GeomagneticElements wmm2025_elements(const GeoPoint& point, double decimal_year);

// The field vector in the world frame (east, north, up), tesla. The world's y axis is true north.
Eigen::Vector3d field_enu_T(const GeomagneticElements& e);

// The same field along a sensor's axes, given the sensor's orientation in the world (the matrix
// whose columns are the sensor's axes in world coordinates).
Eigen::Vector3d field_in_sensor_T(const Eigen::Vector3d& field_enu_T, const Eigen::Matrix3d& world_from_sensor);

}  // namespace sear
