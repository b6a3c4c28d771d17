// What each in-process sensor measured during a run (the truth its model turned into volts,
// levels or registers for the firmware), one CSV per robot, `sensors_<robot>.csv`, for plots.
#pragma once

#include <climits>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "exporters/bounded_file.hpp"
#include "runtime/run_tap.hpp"
#include "scene/description.hpp"

namespace sear {

// Columns: time_s (the sample's time, 9 decimals), mcu, device, quantity, unit, value; one row per
// value of a sample, meanings as tools/lcm/reading_meaning.hpp gives them per element ("inf": no
// echo). Each device is kept to one sample per `period_s` (the trace period: a plot needs no more),
// the first sample always. Robots without such devices get no file.
class SensorCsv final : public RunTap {
 public:
  // MCUs are indexed as Lockstep does: robots in order, each robot's MCUs in order.
  SensorCsv(const std::string& folder, const ProjectDesc& project, double period_s, std::uint64_t max_file_bytes);
  void on_sample(std::size_t mcu, std::size_t device, const sear_link_sample& sample) override;
  void on_step(const Simulation& sim) override;
  void flush();
  std::vector<const BoundedFile*> outputs() const;

 private:
  struct Device {
    std::string name;
    std::string element;
    std::int64_t last_ns = INT64_MIN;
  };
  struct Mcu {
    std::string name;
    BoundedFile* file = nullptr;
    std::vector<Device> devices;
  };
  std::vector<std::unique_ptr<BoundedFile>> files_;
  std::vector<Mcu> mcus_;
  std::int64_t period_ns_;
  bool dirty_ = false;
};

}  // namespace sear
