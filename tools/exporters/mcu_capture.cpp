#include "exporters/mcu_capture.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "exporters/stdout_text.hpp"

namespace sear {
namespace {

std::string seconds(std::int64_t ns) { return fmt::format("{}.{:09d}", ns / 1000000000, ns % 1000000000); }

// "S.NNNNNNNNN tx hh\n" into `line`, which has room for it. A port at 500 kbaud writes 50 000 of
// these a simulated second: fmt, even compiled, took a fifth of the simulator's time there, and
// these few digits by hand a small part of that. Times are never negative.
std::string_view byte_line(char* line, std::int64_t time_ns, bool tx, std::uint8_t value) {
  static const char hex[] = "0123456789abcdef";
  char* p = line;
  auto whole = static_cast<std::uint64_t>(time_ns / 1000000000);
  auto fraction = static_cast<std::uint64_t>(time_ns % 1000000000);
  char digits[20];
  int n = 0;
  do {
    digits[n++] = static_cast<char>('0' + whole % 10);
    whole /= 10;
  } while (whole);
  while (n) *p++ = digits[--n];
  *p++ = '.';
  for (int i = 8; i >= 0; --i, fraction /= 10) p[i] = static_cast<char>('0' + fraction % 10);
  p += 9;
  *p++ = ' ';
  *p++ = tx ? 't' : 'r';
  *p++ = 'x';
  *p++ = ' ';
  *p++ = hex[value >> 4];
  *p++ = hex[value & 15];
  *p++ = '\n';
  return {line, static_cast<std::size_t>(p - line)};
}

}  // namespace

McuCapture::McuCapture(std::string out_dir, std::vector<Mcu> mcus, bool echo, std::uint64_t max_file_bytes)
    : out_dir_(std::move(out_dir)), echo_(echo), max_file_bytes_(max_file_bytes) {
  for (auto& m : mcus) {
    State s;
    s.mcu = m;
    if (m.console_uart >= 0) s.console = open(m.id + ".console.log", text_truncation_note(max_file_bytes_));
    s.pins = open(m.id + ".pins.vcd", vcd_truncation_note(max_file_bytes_));
    s.waveform = std::make_unique<PinWaveform>(*s.pins, m.id, m.waveform_uart_bytes);
    states_.push_back(std::move(s));
  }
}

McuCapture::~McuCapture() = default;

std::unique_ptr<BoundedFile> McuCapture::open(const std::string& name, const std::string& note) {
  auto file = std::make_unique<BoundedFile>(out_dir_ + "/" + name, max_file_bytes_, note);
  all_.push_back(file.get());
  return file;
}

McuCapture::PortFiles& McuCapture::port(State& s, int n) {
  auto it = s.ports.find(n);
  if (it != s.ports.end()) return it->second;
  PortFiles p;
  const std::string stem = fmt::format("{}.uart{}", s.mcu.id, n);
  p.raw_tx = open(stem + ".tx.bin", "");
  p.raw_rx = open(stem + ".rx.bin", "");
  p.text = open(stem + ".log", text_truncation_note(max_file_bytes_));
  p.text->write(fmt::format("# SEAR UART capture: mcu {}, port {}, 8N1\n"
                            "# time_s (end of the stop bit), direction (tx, rx, or baud when the port starts), byte in hex\n",
                            s.mcu.id, n));
  return s.ports.emplace(n, std::move(p)).first->second;
}

void McuCapture::end_line(State& s, std::int64_t time_ns) {
  s.console->write(fmt::format("{} {}\n", seconds(time_ns), s.line));
  if (echo_) print_to_stdout(fmt::format("[{:>11.6f}] {}: {}\n", static_cast<double>(time_ns) * 1e-9, s.mcu.id, s.line));
  s.line.clear();
}

void McuCapture::console_byte(State& s, std::int64_t time_ns, std::uint8_t byte) {
  s.line_time = time_ns;
  if (byte == '\n') end_line(s, time_ns);
  else if (byte != '\r') s.line.push_back(static_cast<char>(byte));
}

void McuCapture::on_event(std::size_t mcu, const sear_event& e) { states_[mcu].pending.push_back(e); }

void McuCapture::on_stop(std::size_t mcu, std::int64_t time_ns) {
  State& s = states_[mcu];
  s.stop_ns = std::min(s.stop_ns, time_ns);
}

void McuCapture::write_event(State& s, const sear_event& e) {
  switch (e.kind) {
    case SEAR_EVENT_UART_BEGIN:
      port(s, e.index).text->write(fmt::format("{} baud {}\n", seconds(e.time_ns), e.value));
      break;
    case SEAR_EVENT_UART_TX:
    case SEAR_EVENT_UART_RX: {
      const bool tx = e.kind == SEAR_EVENT_UART_TX;
      PortFiles& p = port(s, e.index);
      const auto byte = static_cast<char>(e.value);
      (tx ? p.raw_tx : p.raw_rx)->write(std::string_view(&byte, 1));
      char line[40];
      p.text->write(byte_line(line, e.time_ns, tx, static_cast<std::uint8_t>(e.value)));
      if (tx && e.index == s.mcu.console_uart) console_byte(s, e.time_ns, static_cast<std::uint8_t>(e.value));
      break;
    }
    default:
      break;
  }
}

// Events come in time order per kind, but a byte sent is stamped ahead of the pin changes that
// follow it: sorting by time, stably, restores one timeline and keeps the order of equal times.
void McuCapture::release(State& s, std::int64_t until_ns) {
  if (s.pending.empty()) return;
  std::stable_sort(s.pending.begin(), s.pending.end(),
                   [](const sear_event& a, const sear_event& b) { return a.time_ns < b.time_ns; });
  const std::int64_t limit = std::min(until_ns, s.stop_ns);
  std::size_t n = 0, written = 0;
  for (; n < s.pending.size() && s.pending[n].time_ns <= until_ns; ++n) {
    if (s.pending[n].time_ns > limit) continue;
    write_event(s, s.pending[n]);
    ++written;
  }
  // Those written are the first, in time order; at once, as the waveform looks ahead among them.
  s.waveform->write(s.pending.data(), written);
  s.pending.erase(s.pending.begin(), s.pending.begin() + static_cast<std::ptrdiff_t>(n));
}

// Every step's output reaches the files at once (a flush with nothing new costs no system call),
// so that a simulator killed outright has lost nothing it had written, and the logs can be
// followed while the run goes on.
void McuCapture::advance_to(std::int64_t now_ns) {
  for (auto& s : states_) release(s, now_ns);
  for (auto* f : all_) f->flush();
}

void McuCapture::finish(std::int64_t end_ns) {
  for (auto& s : states_) {
    release(s, end_ns);
    s.pending.clear();  // due after the run's end: never on the wire within it
    s.waveform->finish(std::min(end_ns, s.stop_ns));
    if (s.console && !s.line.empty()) end_line(s, s.line_time);
  }
  for (auto* f : all_) f->flush();
}

}  // namespace sear
