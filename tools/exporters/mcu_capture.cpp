#include "exporters/mcu_capture.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

#include "exporters/digit_pairs.hpp"
#include "exporters/stdout_text.hpp"

namespace sear {
namespace {

// How far the waveform stays behind the released events: a frame of ten bits at 300 baud, the
// slowest a port runs at (hal/uart.h), so that no byte's start bit comes before what is written.
constexpr std::int64_t kWaveLagNs = (10 * std::int64_t{1000000000} + 299) / 300;

std::string seconds(std::int64_t ns) { return fmt::format("{}.{:09d}", ns / 1000000000, ns % 1000000000); }

// The lines of a UART log, "S.NNNNNNNNN tx hh\n". A port at 500 kbaud writes 50 000 of these a
// simulated second: fmt, even compiled, took a fifth of the simulator's time there, and these few
// digits by hand a small part of that (the nine below the second, one at a time, were half of
// it). The whole seconds' digits are kept from the line before, as a run of bytes shares them.
// Times are never negative.
class ByteLines {
 public:
  // Writes the line at p, which has room for kMaxLine more bytes; returns its end.
  static constexpr std::size_t kMaxLine = 40;
  char* put(char* p, std::int64_t time_ns, bool tx, std::uint8_t value) {
    static const char hex[] = "0123456789abcdef";
    const std::int64_t second = time_ns / 1000000000;
    if (second != second_) {
      second_ = second;
      auto whole = static_cast<std::uint64_t>(second);
      char digits[20];
      int n = 0;
      do {
        digits[n++] = static_cast<char>('0' + whole % 10);
        whole /= 10;
      } while (whole);
      whole_length_ = 0;
      while (n) whole_[whole_length_++] = digits[--n];
      whole_[whole_length_++] = '.';
    }
    std::memcpy(p, whole_, sizeof whole_);  // a fixed-size copy, of which the length counts
    p += whole_length_;
    const auto nano = static_cast<std::uint32_t>(time_ns % 1000000000);
    *p++ = static_cast<char>('0' + nano / 100000000);
    two_digits(p, nano / 1000000 % 100);
    two_digits(p + 2, nano / 10000 % 100);
    two_digits(p + 4, nano / 100 % 100);
    two_digits(p + 6, nano % 100);
    p += 8;
    std::memcpy(p, tx ? " tx " : " rx ", 4);
    p[4] = hex[value >> 4];
    p[5] = hex[value & 15];
    p[6] = '\n';
    return p + 7;
  }

 private:
  std::int64_t second_ = -1;
  char whole_[24] = {};  // up to 20 digits and the point
  int whole_length_ = 0;
};

}  // namespace

McuCapture::McuCapture(std::string out_dir, std::vector<Mcu> mcus, bool echo, std::uint64_t max_file_bytes)
    : out_dir_(std::move(out_dir)), echo_(echo), max_file_bytes_(max_file_bytes) {
  for (auto& m : mcus) {
    State s;
    s.mcu = m;
    if (m.console_uart >= 0) s.console = open(m.id + ".console.log", text_truncation_note(max_file_bytes_));
    s.pins = open(m.id + ".pins.vcd", vcd_truncation_note(max_file_bytes_));
    s.values = open(m.id + ".values.vcd", vcd_truncation_note(max_file_bytes_));
    s.waveform = std::make_unique<PinWaveform>(*s.pins, *s.values, m.id, m.waveform_uart_bytes, m.pin_labels,
                                               m.uart_frames);
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
  std::unique_ptr<PortFiles>& p = s.ports.at(static_cast<std::size_t>(n));
  if (p) return *p;
  p = std::make_unique<PortFiles>();
  const std::string stem = fmt::format("{}.uart{}", s.mcu.id, n);
  p->raw_tx = open(stem + ".tx.bin", "");
  p->raw_rx = open(stem + ".rx.bin", "");
  p->text = open(stem + ".log", text_truncation_note(max_file_bytes_));
  p->text->write(fmt::format("# SEAR UART capture: mcu {}, port {}, 8N1\n"
                             "# time_s (end of the stop bit), direction (tx, rx, or baud when the port starts), byte in hex\n",
                             s.mcu.id, n));
  return *p;
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

void McuCapture::on_events(std::size_t mcu, const sear_event* events, std::size_t count) {
  states_[mcu].pending.insert(states_[mcu].pending.end(), events, events + count);
}

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
    case SEAR_EVENT_UART_RX:
      write_bytes(s, &e, 1);
      break;
    default:
      break;
  }
}

// Bytes of one kind on one port, in time order: one write to each of the port's files for as many
// as fit in a block, where a byte at a time cost two writes and a search for its port.
void McuCapture::write_bytes(State& s, const sear_event* bytes, std::size_t count) {
  const bool tx = bytes[0].kind == SEAR_EVENT_UART_TX;
  PortFiles& p = port(s, bytes[0].index);
  BoundedFile& raw = *(tx ? p.raw_tx : p.raw_rx);
  const bool console = tx && bytes[0].index == s.mcu.console_uart;
  constexpr std::size_t kBlock = 128;
  char values[kBlock];
  char text[kBlock * ByteLines::kMaxLine];
  ByteLines lines;
  for (std::size_t done = 0; done < count;) {
    const std::size_t block = std::min(count - done, kBlock);
    char* end = text;
    for (std::size_t i = 0; i < block; ++i) {
      const sear_event& e = bytes[done + i];
      const auto value = static_cast<std::uint8_t>(e.value);
      values[i] = static_cast<char>(value);
      end = lines.put(end, e.time_ns, tx, value);
      if (console) console_byte(s, e.time_ns, value);
    }
    raw.write(std::string_view(values, block));
    p.text->write(std::string_view(text, static_cast<std::size_t>(end - text)));
    done += block;
  }
}

// Events come in time order per kind, but a byte sent is stamped ahead of the pin changes that
// follow it: sorting by time, stably, restores one timeline and keeps the order of equal times.
void McuCapture::release(State& s, std::int64_t until_ns) {
  if (s.pending.empty()) return;
  // Most steps' events already are (a stable sort asks for a buffer of its own each time).
  const auto earlier = [](const sear_event& a, const sear_event& b) { return a.time_ns < b.time_ns; };
  if (!std::is_sorted(s.pending.begin(), s.pending.end(), earlier))
    std::stable_sort(s.pending.begin(), s.pending.end(), earlier);
  const std::int64_t limit = std::min(until_ns, s.stop_ns);
  // A waveform that shows no byte needs none of them queued: a stream's bytes go to the logs in
  // runs (a 500 kbaud line brings 50 a millisecond), and queue_wave() sees only bytes shown.
  const bool bytes_shown = s.mcu.waveform_uart_bytes || s.mcu.uart_frames;
  std::size_t n = 0;
  while (n < s.pending.size() && s.pending[n].time_ns <= until_ns) {
    const sear_event& e = s.pending[n];
    if (e.time_ns > limit) {
      keep_unsent(s, e);
      ++n;
      continue;
    }
    if (!bytes_shown && (e.kind == SEAR_EVENT_UART_TX || e.kind == SEAR_EVENT_UART_RX)) {
      std::size_t end = n + 1;
      while (end < s.pending.size() && s.pending[end].kind == e.kind && s.pending[end].index == e.index &&
             s.pending[end].time_ns <= limit)
        ++end;
      write_bytes(s, &e, end - n);
      n = end;
      continue;
    }
    write_event(s, e);
    queue_wave(s, e);
    ++n;
  }
  s.pending.erase(s.pending.begin(), s.pending.begin() + static_cast<std::ptrdiff_t>(n));
  write_wave(s, std::min(until_ns - kWaveLagNs, s.stop_ns));
  if (s.closed_ns < 0 && s.stop_ns <= until_ns) close(s, s.stop_ns, "the MCU stopped");
}

// A byte on a USART's pin, as a logic analyser sees it: the line falls for the start bit ten bit
// times before the stop bit ends, then carries the data bits from the least significant, then
// the stop bit (high); each bit's edge rounded to the nanosecond as the HAL rounds the byte's end.
void McuCapture::queue_wave(State& s, const sear_event& e) {
  s.wave_pending.push(0, e);
  if (!s.mcu.uart_frames || e.index >= SEAR_LINK_UARTS) return;
  std::array<std::int64_t, 10>& before_end = s.wave_before_end[e.index];
  if (e.kind == SEAR_EVENT_UART_BEGIN) {
    s.wave_baud[e.index] = e.value;
    // Worked out once a baud rate rather than with a division for every edge.
    for (int bit = 0; bit < 10 && e.value; ++bit)
      before_end[bit] = ((10 - bit) * std::int64_t{1000000000} + e.value / 2) / e.value;
  }
  if ((e.kind != SEAR_EVENT_UART_TX && e.kind != SEAR_EVENT_UART_RX) || !s.wave_baud[e.index]) return;
  const bool tx = e.kind == SEAR_EVENT_UART_TX;
  const int pin = tx ? PinWaveform::uart_tx_pin(e.index) : PinWaveform::uart_rx_pin(e.index);
  const std::size_t line = 1 + 2 * std::size_t{e.index} + (tx ? 0 : 1);
  int shown = 1;  // idle
  for (int bit = 0; bit < 10; ++bit) {
    const int level = bit == 0 ? 0 : bit == 9 ? 1 : (e.value >> (bit - 1)) & 1;
    if (level == shown) continue;
    shown = level;
    s.wave_pending.push(line, {e.time_ns - before_end[bit], static_cast<std::uint32_t>(level),
                               PinWaveform::kLineLevel, static_cast<std::uint8_t>(pin), {0, 0}});
  }
}

// Writes the queued changes due by until_ns, in time order (stably: the order of equal times is
// the order they came in); at once, as the waveform looks ahead among them.
void McuCapture::write_wave(State& s, std::int64_t until_ns) {
  s.wave_due.clear();
  s.wave_pending.take_until(until_ns, s.wave_due);
  s.waveform->write(s.wave_due.data(), s.wave_due.size());
}

void McuCapture::keep_unsent(State& s, const sear_event& e) {
  if (e.kind == SEAR_EVENT_UART_TX) s.never_sent[e.index].push_back(static_cast<char>(e.value));
}

// The wire stopped at time_ns: a console line cut short says so, and what was still queued
// follows on lines of its own, stamped with that time, so that a firmware's last words are read
// where its other lines are.
void McuCapture::close(State& s, std::int64_t time_ns, const char* why) {
  for (const auto& e : s.pending) keep_unsent(s, e);
  s.pending.clear();
  s.closed_ns = time_ns;
  if (s.console && !s.line.empty()) {
    s.line += fmt::format(" [line not ended: {}]", why);
    end_line(s, s.line_time);
  }
  for (const auto& [port_number, bytes] : s.never_sent) {
    port(s, port_number)
        .text->write(fmt::format("# {}: {} bytes queued never sent: {}\n", seconds(time_ns), bytes.size(), why));
    if (!s.console || port_number != s.mcu.console_uart) continue;
    std::size_t begin = 0;
    while (begin < bytes.size()) {
      const std::size_t end = std::min(bytes.find('\n', begin), bytes.size());
      std::string text = bytes.substr(begin, end - begin);
      text.erase(std::remove(text.begin(), text.end(), '\r'), text.end());
      s.line = "[never sent] " + text;
      end_line(s, time_ns);
      begin = end + 1;
    }
  }
}

std::vector<NeverSent> McuCapture::never_sent() const {
  std::vector<NeverSent> all;
  for (const auto& s : states_)
    for (const auto& [port_number, bytes] : s.never_sent)
      all.push_back({s.mcu.id, port_number, bytes, s.closed_ns, s.stop_ns == s.closed_ns});
  return all;
}

void McuCapture::advance_to(std::int64_t now_ns) {
  for (auto& s : states_) release(s, now_ns);
}

void McuCapture::flush() {
  for (auto* f : all_) f->flush();
}

void McuCapture::finish(std::int64_t end_ns) {
  for (auto& s : states_) {
    release(s, end_ns);
    if (s.closed_ns < 0) close(s, end_ns, "the run ended");  // what is due later never left within it
    write_wave(s, std::min(end_ns, s.stop_ns));
    s.waveform->finish(std::min(end_ns, s.stop_ns));
  }
  for (auto* f : all_) f->flush();
}

}  // namespace sear
