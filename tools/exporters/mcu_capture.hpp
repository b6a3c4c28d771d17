// What each MCU did on its pins and ports, written to the output folder as the run's time passes:
// the console log, every UART's traffic (raw and time-stamped), and the pins, PWM duties and UART
// bytes as VCD waveforms (exporters/pin_waveform.hpp).
// Events wait until the world's time reaches them (a UART byte is stamped with the end of its
// stop bit, which may lie quanta ahead), so nothing is stamped after the run's end or after its
// MCU stopped. Bytes that were still queued then never reached the wire, as on the chip, but they
// are not lost: the console ends with them on lines marked "[never sent]", and never_sent() hands
// them to the summary.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "exporters/bounded_file.hpp"
#include "exporters/edge_streams.hpp"
#include "exporters/pin_waveform.hpp"
#include "runtime/mcu_bridge.hpp"

namespace sear {

// Bytes a firmware had queued on a port that never left it: its MCU stopped, or the run ended.
struct NeverSent {
  std::string mcu;  // "robot.mcu"
  int port;
  std::string bytes;
  std::int64_t time_ns;  // when the wire stopped: the MCU's stop or the run's end
  bool mcu_stopped;      // false: the run ended
};

class McuCapture : public McuListener {
 public:
  struct Mcu {
    std::string id;    // "robot.mcu", the stem of its files
    int console_uart;  // -1: none
    // values.vcd shows each UART byte (PinWaveform). Off in `sear run` unless --uart-frames: at
    // 500 kbaud the bytes are all but 3 kB of the reference rover's file (0.6 MB a simulated
    // second, past the default size limit in seven minutes) and half of what its capture cost,
    // for a view the UART logs already give with the same times.
    bool waveform_uart_bytes = true;
    std::vector<std::string> pin_labels = {};  // what is wired to each pin (exporters/pin_labels.hpp)
    // pins.vcd draws each UART byte's frame on its USART pins. Off by default: at 500 kbaud the
    // frames are 96 % of the file (2 MB a simulated second), which then reaches the default size
    // limit in two minutes and loses every later edge of every pin, and cost the reference rover
    // a fifth of its speed, for a view the bytes in the logs already give.
    bool uart_frames = false;
  };
  // `echo`: console lines also go to standard output, with the MCU and the sim time; a closed
  // standard output ends the echo, not the run. No file grows past `max_file_bytes`.
  McuCapture(std::string out_dir, std::vector<Mcu> mcus, bool echo, std::uint64_t max_file_bytes);
  ~McuCapture() override;

  void on_events(std::size_t mcu, const sear_event* events, std::size_t count) override;
  void on_stop(std::size_t mcu, std::int64_t time_ns) override;
  // Writes every event stamped at or before now_ns.
  void advance_to(std::int64_t now_ns);
  // Pushes what was written to the files (the run does it on a wall-clock period, FlushClock).
  void flush();
  // The run ended at end_ns: writes what is due by then, drops the rest, ends any console line
  // still open and flushes every file, so that all of it is on disk.
  void finish(std::int64_t end_ns);
  // Its files, in the order they were opened, for listing and for reporting those cut short.
  std::vector<const BoundedFile*> outputs() const { return {all_.begin(), all_.end()}; }
  // Every port's queued bytes that never left, per MCU in order; complete once finish() ran.
  std::vector<NeverSent> never_sent() const;

 private:
  struct PortFiles {
    std::unique_ptr<BoundedFile> raw_tx, raw_rx, text;
  };
  struct State {
    Mcu mcu;
    std::unique_ptr<BoundedFile> console, pins, values;
    std::string line;
    std::unique_ptr<PinWaveform> waveform;  // into `pins` and `values`
    std::int64_t line_time = 0;             // of the console's last byte
    std::int64_t stop_ns = INT64_MAX;
    // By port, opened at its first event; the link refuses a port past the chip's. An array, not
    // a map: a 500 kbaud line asks for its files 50 times a millisecond, and a map's search was a
    // fifth of writing its byte.
    std::array<std::unique_ptr<PortFiles>, SEAR_LINK_UARTS> ports;
    std::vector<sear_event> pending;  // not yet due, in the order they came
    std::map<int, std::string> never_sent;  // per port
    std::int64_t closed_ns = -1;            // when its wire stopped: -1 while it runs
    // Released to the waveform but not yet written: a byte's frame begins ten bits before the
    // byte is stamped, so the waveform stays that far behind to keep its time in order. The
    // events are one stream, each UART line's edges another.
    EdgeStreams wave_pending{1 + 2 * SEAR_LINK_UARTS};
    std::vector<sear_event> wave_due;    // what write_wave hands the waveform, kept for its capacity
    std::array<std::uint32_t, SEAR_LINK_UARTS> wave_baud{};
    // Per port, how long before a byte's stamp (the end of its stop bit) each of its ten bits
    // starts, at wave_baud, rounded as the HAL rounds the byte's end.
    std::array<std::array<std::int64_t, 10>, SEAR_LINK_UARTS> wave_before_end{};
  };
  std::unique_ptr<BoundedFile> open(const std::string& name, const std::string& note);
  PortFiles& port(State& s, int port);
  void write_event(State& s, const sear_event& e);
  void write_bytes(State& s, const sear_event* bytes, std::size_t count);
  void console_byte(State& s, std::int64_t time_ns, std::uint8_t byte);
  void end_line(State& s, std::int64_t time_ns);
  void release(State& s, std::int64_t until_ns);
  void keep_unsent(State& s, const sear_event& e);
  void queue_wave(State& s, const sear_event& e);
  void write_wave(State& s, std::int64_t until_ns);
  void close(State& s, std::int64_t time_ns, const char* why);

  std::string out_dir_;
  bool echo_;
  std::uint64_t max_file_bytes_;
  std::vector<State> states_;
  std::vector<BoundedFile*> all_;
};

}  // namespace sear
