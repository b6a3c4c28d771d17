// What each MCU did on its pins and ports, written to the output folder as it happens: the
// console log, every UART's traffic (raw and time-stamped), and the pins as a VCD waveform.
#pragma once

#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "runtime/mcu_bridge.hpp"

namespace sear {

class McuCapture : public McuListener {
 public:
  struct Mcu {
    std::string id;    // "robot.mcu", the stem of its files
    int console_uart;  // -1: none
  };
  // `echo`: console lines also go to standard output, with the MCU and the sim time.
  McuCapture(std::string out_dir, std::vector<Mcu> mcus, bool echo);
  ~McuCapture() override;

  void on_event(std::size_t mcu, const sear_event& event) override;
  // Ends any console line still open and flushes every file, so that all of it is on disk.
  void finish();
  std::vector<std::string> files() const;

 private:
  struct File {
    std::string path;
    std::FILE* f = nullptr;
  };
  struct PortFiles {
    File raw_tx, raw_rx, text;
  };
  struct State {
    Mcu mcu;
    File console, pins;
    std::string line;
    std::int64_t line_time = 0;  // of the console's last byte
    std::int64_t last_pin_time = 0;  // the header's initial values are at #0
    std::map<int, PortFiles> ports;
  };
  File open(const std::string& name);
  PortFiles& port(State& s, int port);
  void console_byte(State& s, std::int64_t time_ns, std::uint8_t byte);
  void end_line(State& s, std::int64_t time_ns);
  void pin_change(State& s, std::int64_t time_ns, int pin, char value);

  std::string out_dir_;
  bool echo_;
  std::vector<State> states_;
  std::vector<std::string> paths_;
};

}  // namespace sear
