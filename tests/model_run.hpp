// Reading back what a run wrote, for the tests that hold its numbers to the model: trace rows by
// time and column name, the chassis pose in them, where a sensor's axis meets a face, and pin
// changes in a VCD.
#pragma once

#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "firmware_run.hpp"

namespace sear::test {

// A trace_<robot>.csv: the header's column names and every row's cells, by time in whole
// microseconds (the time column has 6 decimals).
class Trace {
 public:
  explicit Trace(const std::string& csv) {
    const auto lines = lines_of(csv);
    if (lines.empty()) throw std::runtime_error("empty trace");
    names_ = split(lines[0]);
    for (std::size_t i = 1; i < lines.size(); ++i) {
      const auto cells = split(lines[i]);
      if (cells.size() != names_.size()) throw std::runtime_error("trace row " + std::to_string(i) + ": " + lines[i]);
      time_cells_.push_back(cells[0]);
      const auto us = std::llround(std::stod(cells[0]) * 1e6);
      rows_[us] = cells;
      order_.push_back(us);
    }
  }
  const std::vector<std::string>& names() const { return names_; }
  const std::vector<std::string>& time_cells() const { return time_cells_; }  // as printed, in file order
  const std::vector<long long>& times_us() const { return order_; }
  bool has(long long t_us) const { return rows_.count(t_us) != 0; }
  double at(long long t_us, const std::string& column) const {
    const auto row = rows_.find(t_us);
    if (row == rows_.end()) throw std::runtime_error("no trace row at " + std::to_string(t_us) + " us");
    for (std::size_t c = 0; c < names_.size(); ++c)
      if (names_[c] == column) return std::stod(row->second[c]);
    throw std::runtime_error("no trace column " + column);
  }
  double last(const std::string& column) const { return at(order_.back(), column); }

 private:
  static std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> cells;
    std::istringstream in(line);
    for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
    return cells;
  }
  std::vector<std::string> names_;
  std::vector<std::string> time_cells_;
  std::map<long long, std::vector<std::string>> rows_;
  std::vector<long long> order_;
};

struct Vec3 {
  double x, y, z;
};

// The chassis pose of one trace row: position (world, m) and Z-Y-X roll, pitch, yaw (rad).
struct Pose {
  Vec3 p;
  double roll, pitch, yaw;
  // A vector of the chassis frame (x forward, y left, z up) in the world frame: Rz(yaw) Ry(pitch) Rx(roll) v.
  Vec3 rotate(const Vec3& v) const {
    const double cr = std::cos(roll), sr = std::sin(roll), cp = std::cos(pitch), sp = std::sin(pitch),
                 cy = std::cos(yaw), sy = std::sin(yaw);
    const Vec3 a{v.x, cr * v.y - sr * v.z, sr * v.y + cr * v.z};  // roll about x
    const Vec3 b{cp * a.x + sp * a.z, a.y, -sp * a.x + cp * a.z};  // pitch about y
    return {cy * b.x - sy * b.y, sy * b.x + cy * b.y, b.z};         // yaw about z
  }
};

inline Pose pose_at(const Trace& trace, long long t_us) {
  return {{trace.at(t_us, "x_m"), trace.at(t_us, "y_m"), trace.at(t_us, "z_m")},
          trace.at(t_us, "roll_rad"),
          trace.at(t_us, "pitch_rad"),
          trace.at(t_us, "yaw_rad")};
}

// Distance along the axis of a sensor mounted at `mount` (chassis frame) looking straight ahead
// (yaw_deg = pitch_deg = 0) to the world plane x = face_x, for a chassis at `pose`.
inline double axis_distance_to_x_plane(const Pose& pose, const Vec3& mount, double face_x) {
  const Vec3 offset = pose.rotate(mount);
  const Vec3 axis = pose.rotate({1, 0, 0});
  return (face_x - (pose.p.x + offset.x)) / axis.x;
}

// One VCD identifier's value changes ('z' included), in file order, with their times in the
// file's own units.
struct VcdChange {
  std::int64_t time;
  char value;
};

inline std::vector<VcdChange> vcd_changes(const std::string& vcd, char id) {
  std::vector<VcdChange> changes;
  std::int64_t t = 0;
  bool dumping = false;
  for (const auto& line : lines_of(vcd)) {
    if (line == "$enddefinitions $end") dumping = true;
    if (!dumping || line.empty() || line[0] == '$') continue;
    if (line[0] == '#') t = std::stoll(line.substr(1));
    else if (line.size() == 2 && line[1] == id) changes.push_back({t, line[0]});
  }
  return changes;
}

// The ATmega2560's ADC (datasheet 26.7, "ADC conversion result"): ADC = Vin * 1024 / Vref,
// truncated, 0..1023 (an input at or above Vref reads 1023); 8-bit reads (ADLAR, ADCH) are its
// top 8 bits.
inline unsigned adc_code(double vin, double vref, int bits = 10) {
  double code = std::floor(vin * 1024.0 / vref);
  if (code < 0) code = 0;
  if (code > 1023) code = 1023;
  return static_cast<unsigned>(code) >> (10 - bits);
}

inline char vcd_id_of_pin(int pin) { return static_cast<char>('!' + pin); }  // as SEAR names them

}  // namespace sear::test
