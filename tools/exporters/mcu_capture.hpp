// What each MCU did on its pins and ports, written to the output folder as the run's time passes:
// the console log, every UART's traffic (raw and time-stamped), and the pins, PWM duties and UART
// bytes as a VCD waveform (exporters/pin_waveform.hpp).
// Events wait until the world's time reaches them (a UART byte is stamped with the end of its
// stop bit, which may lie quanta ahead), so nothing is stamped after the run's end or after its
// MCU stopped.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "exporters/bounded_file.hpp"
#include "exporters/pin_waveform.hpp"
#include "runtime/mcu_bridge.hpp"

namespace sear {

class McuCapture : public McuListener {
 public:
  struct Mcu {
    std::string id;    // "robot.mcu", the stem of its files
    int console_uart;  // -1: none
    bool waveform_uart_bytes = true;  // the VCD shows each UART byte (PinWaveform)
  };
  // `echo`: console lines also go to standard output, with the MCU and the sim time; a closed
  // standard output ends the echo, not the run. No file grows past `max_file_bytes`.
  McuCapture(std::string out_dir, std::vector<Mcu> mcus, bool echo, std::uint64_t max_file_bytes);
  ~McuCapture() override;

  void on_event(std::size_t mcu, const sear_event& event) override;
  void on_stop(std::size_t mcu, std::int64_t time_ns) override;
  // Writes every event stamped at or before now_ns.
  void advance_to(std::int64_t now_ns);
  // The run ended at end_ns: writes what is due by then, drops the rest, ends any console line
  // still open and flushes every file, so that all of it is on disk.
  void finish(std::int64_t end_ns);
  // Its files, in the order they were opened, for listing and for reporting those cut short.
  std::vector<const BoundedFile*> outputs() const { return {all_.begin(), all_.end()}; }

 private:
  struct PortFiles {
    std::unique_ptr<BoundedFile> raw_tx, raw_rx, text;
  };
  struct State {
    Mcu mcu;
    std::unique_ptr<BoundedFile> console, pins;
    std::string line;
    std::unique_ptr<PinWaveform> waveform;  // into `pins`
    std::int64_t line_time = 0;             // of the console's last byte
    std::int64_t stop_ns = INT64_MAX;
    std::map<int, PortFiles> ports;
    std::vector<sear_event> pending;  // not yet due, in the order they came
  };
  std::unique_ptr<BoundedFile> open(const std::string& name, const std::string& note);
  PortFiles& port(State& s, int port);
  void write_event(State& s, const sear_event& e);
  void console_byte(State& s, std::int64_t time_ns, std::uint8_t byte);
  void end_line(State& s, std::int64_t time_ns);
  void release(State& s, std::int64_t until_ns);

  std::string out_dir_;
  bool echo_;
  std::uint64_t max_file_bytes_;
  std::vector<State> states_;
  std::vector<BoundedFile*> all_;
};

}  // namespace sear
