// What each in-process sensor measured during a run (the truth its model turned into volts,
// levels or registers for the firmware) and what its model gave the firmware, one CSV per robot,
// `sensors_<robot>.csv`, for plots.
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

struct ReadingMeaning;  // lcm/reading_meaning.hpp

// Columns: time_s (9 decimals), mcu, device, quantity, unit, value, source; one row per value.
// source "truth": a sample's value at its time, meanings as reading_meaning() in
// tools/lcm/reading_meaning.hpp gives them per element ("inf": no echo). source "reading": what
// the model gave the firmware from time_s on (volts, a level, an echo's width, a count, its data
// registers decoded in SI), meanings as output_meaning() gives them; where it measures the same
// quantity as the truth, quantity and unit are the truth's. Each device is kept to one sample and
// one reading per `period_s` (the trace period: a plot needs no more), the first always; a
// reading held back is written one period after the last, so the latest one is never lost.
// Robots without such devices get no file.
class SensorCsv final : public RunTap {
 public:
  // MCUs are indexed as Lockstep does: robots in order, each robot's MCUs in order.
  SensorCsv(const std::string& folder, const ProjectDesc& project, double period_s, std::uint64_t max_file_bytes);
  void on_sample(std::size_t mcu, std::size_t device, const sear_link_sample& sample) override;
  void on_reading(std::size_t mcu, std::size_t device, std::int64_t time_ns, const double* values,
                  std::size_t count) override;
  void on_step(const Simulation& sim) override;
  // Pushes the rows written to the files.
  void flush();
  // Writes the readings still held back, and flushes; at the end of a run.
  void finish();
  std::vector<const BoundedFile*> outputs() const;

 private:
  struct Device {
    std::string name;
    std::string element;
    std::int64_t last_ns = INT64_MIN;
    std::int64_t reading_written_ns = INT64_MIN;  // the time of the last reading written
    bool reading_held = false;                    // a newer one waits in held_*
    std::int64_t held_ns = 0;
    std::vector<double> held;
  };
  struct Mcu {
    std::string name;
    BoundedFile* file = nullptr;
    std::vector<Device> devices;
  };
  void write_reading(Mcu& m, Device& d);
  // One row per quantity of `meaning` (at most `count` values), from `source` ("truth", "reading").
  static void write_rows(Mcu& m, const Device& d, const ReadingMeaning& meaning, std::int64_t time_ns,
                         const double* values, std::size_t count, const char* source);
  std::vector<std::unique_ptr<BoundedFile>> files_;
  std::vector<Mcu> mcus_;
  std::int64_t period_ns_;
};

}  // namespace sear
