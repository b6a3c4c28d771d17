#include "exporters/mcu_capture.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace sear {
namespace {

// VCD identifiers: one printable character per pin, from '!' on (IEEE 1364 section 18.2).
char vcd_id(int pin) { return static_cast<char>('!' + pin); }

void put(std::FILE* f, const std::string& text) { std::fwrite(text.data(), 1, text.size(), f); }

std::string seconds(std::int64_t ns) { return fmt::format("{}.{:09d}", ns / 1000000000, ns % 1000000000); }

}  // namespace

McuCapture::McuCapture(std::string out_dir, std::vector<Mcu> mcus, bool echo)
    : out_dir_(std::move(out_dir)), echo_(echo) {
  for (auto& m : mcus) {
    State s;
    s.mcu = m;
    if (m.console_uart >= 0) s.console = open(m.id + ".console.log");
    s.pins = open(m.id + ".pins.vcd");
    put(s.pins.f, fmt::format("$comment SEAR pin levels of mcu {} $end\n$timescale 1 ns $end\n$scope module {} $end\n",
                              m.id, m.id));
    for (int pin = 0; pin < SEAR_LINK_PINS; ++pin) put(s.pins.f, fmt::format("$var wire 1 {} D{} $end\n", vcd_id(pin), pin));
    put(s.pins.f, "$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n");
    for (int pin = 0; pin < SEAR_LINK_PINS; ++pin) put(s.pins.f, fmt::format("z{}\n", vcd_id(pin)));
    put(s.pins.f, "$end\n");
    states_.push_back(std::move(s));
  }
}

McuCapture::~McuCapture() {
  try {
    finish();
  } catch (const std::exception&) {
    // Already reported by the finish() that the run calls; closing is all that is left.
  }
  for (auto& s : states_) {
    if (s.console.f) std::fclose(s.console.f);
    std::fclose(s.pins.f);
    for (auto& [n, p] : s.ports) {
      std::fclose(p.raw_tx.f);
      std::fclose(p.raw_rx.f);
      std::fclose(p.text.f);
    }
  }
}

McuCapture::File McuCapture::open(const std::string& name) {
  File file{out_dir_ + "/" + name, nullptr};
  file.f = std::fopen(file.path.c_str(), "wb");
  if (!file.f) throw std::runtime_error(fmt::format("{}: error: cannot write: {}", file.path, std::strerror(errno)));
  paths_.push_back(file.path);
  return file;
}

std::vector<std::string> McuCapture::files() const { return paths_; }

McuCapture::PortFiles& McuCapture::port(State& s, int n) {
  auto it = s.ports.find(n);
  if (it != s.ports.end()) return it->second;
  PortFiles p;
  const std::string stem = fmt::format("{}.uart{}", s.mcu.id, n);
  p.raw_tx = open(stem + ".tx.bin");
  p.raw_rx = open(stem + ".rx.bin");
  p.text = open(stem + ".log");
  put(p.text.f, fmt::format("# SEAR UART capture: mcu {}, port {}, 8N1\n"
                            "# time_s (end of the stop bit), direction (tx, rx, or baud when the port starts), byte in hex\n",
                            s.mcu.id, n));
  return s.ports.emplace(n, p).first->second;
}

void McuCapture::end_line(State& s, std::int64_t time_ns) {
  put(s.console.f, fmt::format("{} {}\n", seconds(time_ns), s.line));
  if (echo_) fmt::print("[{:>11.6f}] {}: {}\n", static_cast<double>(time_ns) * 1e-9, s.mcu.id, s.line);
  s.line.clear();
}

void McuCapture::console_byte(State& s, std::int64_t time_ns, std::uint8_t byte) {
  s.line_time = time_ns;
  if (byte == '\n') end_line(s, time_ns);
  else if (byte != '\r') s.line.push_back(static_cast<char>(byte));
}

void McuCapture::pin_change(State& s, std::int64_t time_ns, int pin, char value) {
  if (time_ns != s.last_pin_time) put(s.pins.f, fmt::format("#{}\n", time_ns));
  s.last_pin_time = time_ns;
  put(s.pins.f, fmt::format("{}{}\n", value, vcd_id(pin)));
}

void McuCapture::on_event(std::size_t mcu, const sear_event& e) {
  State& s = states_[mcu];
  switch (e.kind) {
    case SEAR_EVENT_PIN:
      pin_change(s, e.time_ns, e.index, e.value ? '1' : '0');
      break;
    case SEAR_EVENT_PIN_MODE:
      if (e.value != 1) pin_change(s, e.time_ns, e.index, 'z');  // an input: the MCU drives nothing
      break;
    case SEAR_EVENT_UART_BEGIN:
      put(port(s, e.index).text.f, fmt::format("{} baud {}\n", seconds(e.time_ns), e.value));
      break;
    case SEAR_EVENT_UART_TX:
    case SEAR_EVENT_UART_RX: {
      const bool tx = e.kind == SEAR_EVENT_UART_TX;
      PortFiles& p = port(s, e.index);
      const auto byte = static_cast<std::uint8_t>(e.value);
      std::fputc(byte, tx ? p.raw_tx.f : p.raw_rx.f);
      put(p.text.f, fmt::format("{} {} {:02x}\n", seconds(e.time_ns), tx ? "tx" : "rx", byte));
      if (tx && e.index == s.mcu.console_uart) console_byte(s, e.time_ns, byte);
      break;
    }
    default:
      break;
  }
}

void McuCapture::finish() {
  for (auto& s : states_) {
    if (s.console.f && !s.line.empty()) end_line(s, s.line_time);
    const auto flush = [](const File& f) {
      if (f.f && (std::fflush(f.f) != 0 || std::ferror(f.f)))
        throw std::runtime_error(fmt::format("{}: error: write failed", f.path));
    };
    flush(s.console);
    flush(s.pins);
    for (auto& [n, p] : s.ports) {
      flush(p.raw_tx);
      flush(p.raw_rx);
      flush(p.text);
    }
  }
}

}  // namespace sear
