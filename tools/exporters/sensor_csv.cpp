#include "exporters/sensor_csv.hpp"

#include <fmt/compile.h>
#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <iterator>

#include "lcm/reading_meaning.hpp"
#include "runtime/simulation.hpp"
#include "scene/device_kind.hpp"

namespace sear {

SensorCsv::SensorCsv(const std::string& folder, const ProjectDesc& project, double period_s,
                     std::uint64_t max_file_bytes)
    : period_ns_(std::llround(period_s * 1e9)) {
  for (const RobotDesc& robot : project.robots) {
    BoundedFile* file = nullptr;
    for (const McuDesc& mcu : robot.mcus) {
      Mcu m;
      m.name = mcu.name;
      for (const DeviceDesc& d : mcu.devices) {
        Device device;
        device.name = d.name;
        device.element = d.kind ? d.kind->element : "";
        m.devices.push_back(std::move(device));
      }
      // Only kinds with models in the firmware's process send samples.
      bool samples = false;
      for (const DeviceDesc& d : mcu.devices) samples = samples || (d.kind && d.kind->link_inputs > 0);
      if (samples && !file) {
        files_.push_back(std::make_unique<BoundedFile>(folder + "/sensors_" + robot.name + ".csv", max_file_bytes,
                                                       text_truncation_note(max_file_bytes)));
        file = files_.back().get();
        file->write("time_s,mcu,device,quantity,unit,value,source\n");
      }
      m.file = samples ? file : nullptr;
      mcus_.push_back(std::move(m));
    }
  }
}

void SensorCsv::on_sample(std::size_t mcu, std::size_t device, const sear_link_sample& sample) {
  if (mcu >= mcus_.size() || !mcus_[mcu].file || device >= mcus_[mcu].devices.size()) return;
  Mcu& m = mcus_[mcu];
  Device& d = m.devices[device];
  if (d.last_ns != INT64_MIN && sample.time_ns < d.last_ns + period_ns_) return;
  d.last_ns = sample.time_ns;
  write_rows(m, d, reading_meaning(d.element), sample.time_ns, sample.value, SEAR_LINK_SAMPLE_VALUES, "truth");
}

// Compiled formats: a runtime one was parsed again for every row (a row a step, and more, on the
// reference rover).
void SensorCsv::write_rows(Mcu& m, const Device& d, const ReadingMeaning& meaning, std::int64_t time_ns,
                           const double* values, std::size_t count, const char* source) {
  std::string rows;
  const std::size_t n = std::min(meaning.quantity.size(), count);
  for (std::size_t i = 0; i < n; ++i)
    fmt::format_to(std::back_inserter(rows), FMT_COMPILE("{:.9f},{},{},{},{},{},{}\n"),
                   static_cast<double>(time_ns) * 1e-9, m.name, d.name, meaning.quantity[i], meaning.unit[i],
                   values[i], source);
  m.file->write(rows);
}

void SensorCsv::on_reading(std::size_t mcu, std::size_t device, std::int64_t time_ns, const double* values,
                           std::size_t count) {
  if (mcu >= mcus_.size() || !mcus_[mcu].file || device >= mcus_[mcu].devices.size()) return;
  Mcu& m = mcus_[mcu];
  Device& d = m.devices[device];
  d.held_ns = time_ns;
  d.held.assign(values, values + std::min<std::size_t>(count, SEAR_LINK_SAMPLE_VALUES));
  d.reading_held = true;
  if (d.reading_written_ns == INT64_MIN || time_ns >= d.reading_written_ns + period_ns_) write_reading(m, d);
}

void SensorCsv::write_reading(Mcu& m, Device& d) {
  write_rows(m, d, output_meaning(d.element), d.held_ns, d.held.data(), d.held.size(), "reading");
  d.reading_written_ns = d.held_ns;
  d.reading_held = false;
}

// A reading held back goes out once a period has passed since the last one written: a model whose
// output then stays put still shows its latest value.
void SensorCsv::on_step(const Simulation& sim) {
  for (Mcu& m : mcus_)
    for (Device& d : m.devices)
      if (d.reading_held && sim.time_ns() >= d.reading_written_ns + period_ns_) write_reading(m, d);
}

void SensorCsv::flush() {
  for (auto& f : files_) f->flush();
}

void SensorCsv::finish() {
  for (Mcu& m : mcus_)
    for (Device& d : m.devices)
      if (d.reading_held && m.file) write_reading(m, d);
  flush();
}

std::vector<const BoundedFile*> SensorCsv::outputs() const {
  std::vector<const BoundedFile*> out;
  for (const auto& f : files_) out.push_back(f.get());
  return out;
}

}  // namespace sear
