// One MCU's panel in the viewer: the levels, duties and pulses its firmware drives, what its
// devices' models gave it and were fed, its console lines and each UART device's traffic, kept
// from the run's hooks at little cost per event and turned into JSON for a frame.
#pragma once

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lockstep_link.h"
#include "scene/description.hpp"
#include "view/mcu_panel_log.hpp"
#include "view/scene_json.hpp"
#include "view/uart_decode.hpp"

namespace sear {

// Console lines longer than this are cut into pieces: a firmware that never prints '\n' still shows.
constexpr std::size_t kMaxConsoleLine = 512;

struct PanelDevice {
  std::string name;
  std::string element;
  SensorView view = SensorView::None;
  bool has_truth = false;
  std::array<double, SEAR_LINK_SAMPLE_VALUES> truth{};
  std::size_t truth_count = 0;
  std::vector<double> reading;  // empty until the model said something
  std::unique_ptr<UartStream> to_device, from_device;  // UART devices only
};

class McuPanel {
 public:
  McuPanel(const McuDesc& desc, std::string id, int index);

  const std::string& id() const { return id_; }
  const std::string& can_bus() const { return can_bus_; }
  const std::vector<PanelDevice>& devices() const { return devices_; }

  void on_event(const sear_event& e, LogRing& log);
  void on_sample(std::size_t device, const sear_link_sample& sample);
  void on_reading(std::size_t device, const double* values, std::size_t count);
  void on_wire_bytes(std::size_t device, bool from_device, const serial_byte* bytes, std::size_t count, LogRing& log);
  void stopped(const std::string& why) { stopped_ = why; }
  // The chip's cycles so far and how many were busy (an engine that counts them: the AVR's).
  void on_chip_cycles(std::uint64_t cycles, std::uint64_t busy);
  // Not watching: UART traffic is neither decoded nor logged (console lines, levels, samples and
  // readings still are: they cost little). Watching again, each UART stream resumes at its next
  // message boundary ('$', STX) so that no torn message shows.
  void set_watching(bool watching);
  void reset();

  // "running", "stopped", "cpu_load" (the busy share of the chip's last 100 ms, null where the
  // engine cannot tell), "pins", "pwm", "servo", "readings", "truth" into `out`.
  void put_state(nlohmann::ordered_json& out) const;

 private:
  std::string id_;
  int index_;
  int console_uart_;
  std::string can_bus_;
  std::vector<PanelDevice> devices_;
  std::map<int, int> pins_, pwm_, servo_;
  std::string console_;           // the line being printed
  std::string stopped_;           // empty: running
  double clock_hz_;
  std::uint64_t window_cycles_ = 0, window_busy_ = 0;  // where the load's window began
  double cpu_load_ = -1;                                // the last whole window's; < 0: none yet
  bool watching_ = true;
  std::vector<LogEntry> decoded_;  // scratch for UART streams
};

}  // namespace sear
