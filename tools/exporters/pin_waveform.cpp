#include "exporters/pin_waveform.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cstring>

#include "exporters/digit_pairs.hpp"
#include "scene/board_pins.hpp"

namespace sear {
namespace {

// VCD identifiers are printable characters '!'..'~' (IEEE 1364 section 18.2.1): pin n keeps its
// one character '!' + n, as before; the variables after the pins count on in base 94.
std::string vcd_id(int n) {
  std::string id;
  do {
    id += static_cast<char>('!' + n % 94);
    n /= 94;
  } while (n);
  return id;
}

constexpr int kPwmBits = 8;     // pwm_write's duty, 0..255
constexpr int kServoBits = 12;  // servo_write_us's pulse, at most 2600 us
constexpr int kUartBits = 8;    // 8N1

}  // namespace

bool PinWaveform::has_pwm(int pin) { return mega2560_has_pwm(pin); }

bool PinWaveform::has_servo(int pin) {
  return pin == 2 || pin == 3 || pin == 5 || pin == 6 || pin == 7 || pin == 8 || pin == 11 || pin == 12 ||
         (pin >= 44 && pin <= 46);
}

int PinWaveform::uart_tx_pin(int port) { return mega2560_uart_tx_pin(port); }

int PinWaveform::uart_rx_pin(int port) { return mega2560_uart_rx_pin(port); }

PinWaveform::PinWaveform(BoundedFile& pins, BoundedFile& values, const std::string& mcu_id, bool uart_bytes,
                         const std::vector<std::string>& labels, bool uart_frames)
    : pins_(pins), values_(values), uart_bytes_(uart_bytes), uart_frames_(uart_frames) {
  // "name" -> "name_label" where the pin is wired, else "name".
  const auto wired = [&](std::string name, int pin) {
    if (pin < static_cast<int>(labels.size()) && !labels[pin].empty()) name += "_" + labels[pin];
    return name;
  };
  const std::string scope = fmt::format("$timescale 1 ns $end\n$scope module {} $end\n", mcu_id);
  std::string header = fmt::format("$comment SEAR pin levels of mcu {} $end\n", mcu_id);
  if (!uart_frames)
    header += "$comment A begun USART's pins show x: sear run --uart-frames draws each byte's frame on them $end\n";
  header += scope;
  std::string initial;
  for (int pin = 0; pin < SEAR_LINK_PINS; ++pin) {
    header += fmt::format("$var wire 1 {} {} $end\n", vcd_id(pin), wired(fmt::format("D{}", pin), pin));
    initial += fmt::format("z{}\n", vcd_id(pin));
  }
  for (int port = 0; port < kPorts; ++port) set_baud(port, 0);
  mode_.fill(0);    // INPUT, as at reset
  driven_.fill(2);  // nothing outside drives it
  pins_.file.write(header + "$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n" + initial + "$end\n");

  header = fmt::format("$comment SEAR PWM duties (0..255), servo pulses (us){} of mcu {} $end\n",
                       uart_bytes_ ? " and UART bytes" : "", mcu_id);
  if (!uart_bytes_)
    header += "$comment UART bytes are in the UART logs: sear run --uart-frames shows them here too $end\n";
  header += scope;
  initial.clear();
  int next = 0;
  auto declare = [&](int bits, const std::string& name) {
    std::string id = vcd_id(next++);
    header += fmt::format("$var reg {} {} {} $end\n", bits, id, name);
    initial += fmt::format("bz {}\n", id);
    return id;
  };
  // The UART lines first: they change most often, and so get one-character identifiers.
  for (int port = 0; port < kPorts && uart_bytes_; ++port) {
    lines_[2 * port].id = declare(kUartBits, wired(fmt::format("uart{}_tx", port), uart_tx_pin(port)));
    lines_[2 * port + 1].id = declare(kUartBits, wired(fmt::format("uart{}_rx", port), uart_rx_pin(port)));
  }
  for (int pin = 0; pin < SEAR_LINK_PINS; ++pin) {
    duty_[pin] = servo_[pin] = -1;
    if (has_pwm(pin)) duty_id_[pin] = declare(kPwmBits, wired(fmt::format("D{}_pwm", pin), pin));
    if (has_servo(pin)) servo_id_[pin] = declare(kServoBits, wired(fmt::format("D{}_servo_us", pin), pin));
  }
  values_.file.write(header + "$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n" + initial + "$end\n");
}

// Events reach here sorted by time; a VCD whose time ran backwards would be unreadable, so a
// change that came late is kept at the latest time written rather than breaking the file. The
// values' bytes that end by then are written first.
//
// A 500 kbaud line's edges make a stamp every microsecond or two, and std::to_chars on eleven
// digits was a tenth of the simulator's instructions on the reference rover: the milliseconds'
// digits are kept from the stamp before, and only the six below them written, two at a time.
void PinWaveform::stamp(Stream& stream, std::int64_t time_ns) {
  if (&stream == &values_) end_bytes(time_ns);
  if (time_ns <= stream.last_ns) return;
  stream.last_ns = time_ns;
  char line[1 + sizeof stream.ms_text + 6 + 1];  // not initialised: a memset cost as much as the digits
  line[0] = '#';
  char* end = line + 1;
  const std::int64_t ms = time_ns / 1000000;
  if (ms == 0) {
    end = std::to_chars(end, line + sizeof line, time_ns).ptr;
  } else {
    if (ms != stream.ms) {
      stream.ms = ms;
      stream.ms_len = static_cast<std::size_t>(
          std::to_chars(stream.ms_text, stream.ms_text + sizeof stream.ms_text, ms).ptr - stream.ms_text);
    }
    std::memcpy(end, stream.ms_text, sizeof stream.ms_text);  // the whole buffer: a fixed-size copy
    end += stream.ms_len;
    const auto below = static_cast<std::uint32_t>(time_ns - ms * 1000000);
    two_digits(end, below / 10000);
    two_digits(end + 2, below / 100 % 100);
    two_digits(end + 4, below % 100);
    end += 6;
  }
  *end++ = '\n';
  put(stream, line, static_cast<std::size_t>(end - line));
}

// An input shows what a device drives onto it, else its pull-up's high, else nothing ('z').
void PinWaveform::show_input(std::int64_t time_ns, int pin) {
  const std::uint8_t d = driven_[pin];
  level(time_ns, pin, d == 0 ? '0' : d == 1 ? '1' : mode_[pin] == 2 ? '1' : 'z');
}

void PinWaveform::level(std::int64_t time_ns, int pin, char value) {
  stamp(pins_, time_ns);
  const char line[3] = {value, static_cast<char>('!' + pin), '\n'};
  put(pins_, line, 3);
}

void PinWaveform::vector(std::int64_t time_ns, const std::string& id, int value) {
  stamp(values_, time_ns);
  char line[48];
  line[0] = 'b';
  line[1] = 'z';
  char* end = line + 2;
  // Binary without leading zeros, which a reader extends with zeros (section 18.2.1).
  if (value >= 0) end = std::to_chars(line + 1, line + 20, value, 2).ptr;
  *end++ = ' ';
  const std::size_t n = std::min(id.size(), sizeof line - 21);  // ids are at most 2 characters
  std::memcpy(end, id.data(), n);
  end += n;
  *end++ = '\n';
  put(values_, line, static_cast<std::size_t>(end - line));
}

void PinWaveform::flush_text(Stream& stream) {
  if (!stream.text_len) return;
  stream.file.write(std::string_view(stream.text, stream.text_len));
  stream.text_len = 0;
}

// Back to back: this frame started at the last one's stop bit end, which with each end rounded
// to the nanosecond is ten bit times later give or take 2 ns; half a bit allows that, and an
// idle line between frames lasts at least a whole bit.
bool PinWaveform::joins(const Line& line, std::int64_t time_ns, int value) {
  return line.end_ns >= 0 && time_ns >= line.end_ns && time_ns <= line.end_ns + line.bit_ns * 3 / 2 &&
         line.value != value;
}

// Worked out once a baud rate rather than with two divisions a byte.
void PinWaveform::set_baud(int port, std::uint32_t baud) {
  const std::int64_t b = baud ? baud : 9000000;
  port_bit_ns_[port] = (std::int64_t{1000000000} + b / 2) / b;
  port_show_ns_[port] = (kByteBits * std::int64_t{1000000000} + b / 2) / b;
}

void PinWaveform::byte(std::int64_t time_ns, int port, bool tx, std::uint8_t value) {
  Line& line = lines_[2 * port + (tx ? 0 : 1)];
  if (joins(line, time_ns, value)) line.end_ns = -1;  // no 'z' between
  vector(time_ns, line.id, value);
  line.value = value;
  line.bit_ns = port_bit_ns_[port];
  line.end_ns = time_ns + port_show_ns_[port];
  next_end_ns_ = std::min(next_end_ns_, line.end_ns);
}

// Whether `line`'s next byte in the events not yet written joins it.
bool PinWaveform::joined_ahead(const Line& line) const {
  for (const sear_event* e = ahead_; e < ahead_end_; ++e) {
    if ((e->kind != SEAR_EVENT_UART_TX && e->kind != SEAR_EVENT_UART_RX) || e->index >= kPorts) continue;
    if (&lines_[2 * e->index + (e->kind == SEAR_EVENT_UART_TX ? 0 : 1)] == &line)
      return joins(line, e->time_ns, static_cast<int>(e->value & 255));
  }
  return false;
}

// Writes the ends due by until_ns in time order, among themselves and before anything later.
void PinWaveform::end_bytes(std::int64_t until_ns) {
  while (next_end_ns_ <= until_ns) {
    Line* first = nullptr;
    next_end_ns_ = INT64_MAX;
    for (auto& line : lines_) {
      if (line.end_ns < 0) continue;
      if (!first || line.end_ns < first->end_ns) first = &line;
    }
    if (!first) return;
    if (first->end_ns > until_ns) {
      next_end_ns_ = first->end_ns;
      return;
    }
    const std::int64_t t = first->end_ns;
    const bool joined = joined_ahead(*first);
    first->end_ns = -1;
    if (!joined) vector(t, first->id, -1);  // its stamp() finds this end written
    for (const auto& line : lines_)
      if (line.end_ns >= 0) next_end_ns_ = std::min(next_end_ns_, line.end_ns);
  }
}

void PinWaveform::show(std::int64_t time_ns, int& shown, const std::string& id, int value) {
  if (shown == value) return;
  shown = value;
  vector(time_ns, id, value);
}

void PinWaveform::write_one(const sear_event& e) {
  const int i = e.index;
  const auto value = static_cast<int>(e.value & 0xFFFF);  // a duty, a pulse or a byte
  switch (e.kind) {
    case SEAR_EVENT_PIN:
      if (i >= SEAR_LINK_PINS) return;
      level(e.time_ns, i, value ? '1' : '0');
      // After a pwm_write, a plain level is the duty it amounts to: pwm_write(pin, 0) and 255
      // drive levels, as analogWrite() does, and a digital write ends the waveform.
      if (pwm_started_[i]) show(e.time_ns, duty_[i], duty_id_[i], value ? 255 : 0);
      break;
    case SEAR_EVENT_PIN_MODE:
      if (i >= SEAR_LINK_PINS) return;
      mode_[i] = static_cast<std::uint8_t>(value);
      if (value == 1) return;  // an output's level follows as a PIN event
      show_input(e.time_ns, i);
      pwm_started_[i] = false;
      if (!duty_id_[i].empty()) show(e.time_ns, duty_[i], duty_id_[i], -1);
      if (!servo_id_[i].empty()) show(e.time_ns, servo_[i], servo_id_[i], -1);
      break;
    case SEAR_EVENT_PWM:
      if (i >= SEAR_LINK_PINS || duty_id_[i].empty()) return;
      pwm_started_[i] = true;
      show(e.time_ns, duty_[i], duty_id_[i], value & 255);
      break;
    case SEAR_EVENT_SERVO:  // 0: the pulses stopped
      if (i >= SEAR_LINK_PINS || servo_id_[i].empty()) return;
      show(e.time_ns, servo_[i], servo_id_[i], value & 4095);
      break;
    case SEAR_EVENT_UART_BEGIN:
      if (i >= kPorts) return;
      set_baud(i, e.value);
      // The USART takes both pins over; each line idles high between frames, if they are drawn.
      level(e.time_ns, uart_tx_pin(i), uart_frames_ ? '1' : 'x');
      level(e.time_ns, uart_rx_pin(i), uart_frames_ ? '1' : 'x');
      break;
    case kLineLevel:
      if (i < SEAR_LINK_PINS) level(e.time_ns, i, value ? '1' : '0');
      break;
    case SEAR_EVENT_PIN_DRIVEN:
      if (i >= SEAR_LINK_PINS) return;
      driven_[i] = static_cast<std::uint8_t>(value);
      if (mode_[i] != 1) show_input(e.time_ns, i);
      break;
    case SEAR_EVENT_UART_TX:
    case SEAR_EVENT_UART_RX:
      if (i < kPorts && uart_bytes_) byte(e.time_ns, i, e.kind == SEAR_EVENT_UART_TX, static_cast<std::uint8_t>(value));
      break;
    default:
      break;
  }
}

void PinWaveform::write(const sear_event* events, std::size_t count) {
  ahead_end_ = events + count;
  // The text goes to the file a buffer of whole lines at a time (put()); at its size limit the
  // file keeps the lines of that buffer that fit (BoundedFile). A write per event was a tenth of
  // the capture's time on a 500 kbaud line's edges.
  for (ahead_ = events; ahead_ < ahead_end_;) write_one(*ahead_++);
  flush_text(pins_);
  flush_text(values_);
  ahead_ = ahead_end_ = nullptr;
}

void PinWaveform::finish(std::int64_t end_ns) {
  end_bytes(end_ns);
  flush_text(pins_);
  flush_text(values_);
}

}  // namespace sear
