#include "view/uart_decode.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>

extern "C" {
#include "devices/sick_lms2xx.h"
}

namespace sear {
namespace {

// NMEA allows 82 characters a sentence; a longer "line" is not one (binary, or a wrong baud).
constexpr std::size_t kMaxSentence = 120;
// Raw bytes are cut into entries of at most this many.
constexpr std::size_t kMaxRawEntry = 64;

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

std::vector<std::string> fields_of(const std::string& sentence) {
  std::vector<std::string> f;
  const std::size_t end = sentence.find('*');
  std::string cur;
  for (std::size_t i = 0; i < std::min(end, sentence.size()); ++i) {
    if (sentence[i] == ',') {
      f.push_back(cur);
      cur.clear();
    } else {
      cur += sentence[i];
    }
  }
  f.push_back(cur);
  return f;
}

// "ddmm.mmmm" (or "dddmm.mmmm") and its hemisphere, as signed degrees.
std::optional<double> nmea_angle(const std::string& value, const std::string& hemisphere) {
  if (value.empty() || hemisphere.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (*end) return std::nullopt;
  const double degrees = std::floor(v / 100);
  const double angle = degrees + (v - 100 * degrees) / 60;
  return hemisphere == "S" || hemisphere == "W" ? -angle : angle;
}

const char* lms_command_name(std::uint8_t c) {
  switch (c) {
    case LMS2XX_CMD_RESET: return "reset";
    case LMS2XX_CMD_MODE: return "mode";
    case LMS2XX_CMD_VALUES: return "values request";
    case LMS2XX_CMD_STATUS: return "status request";
    case LMS2XX_CMD_ERRORS: return "errors request";
    case LMS2XX_CMD_TYPE: return "type request";
    case LMS2XX_CMD_VARIANT: return "variant";
    case LMS2XX_CMD_READ_CONFIG: return "read config";
    case LMS2XX_CMD_WRITE_CONFIG: return "write config";
    case LMS2XX_REPLY_POWER_ON: return "power-on";
    case LMS2XX_REPLY_RESET: return "reset acknowledged";
    case LMS2XX_REPLY_NOT_RECOGNISED: return "not recognised";
    case LMS2XX_CMD_MODE + 0x80: return "mode reply";
    case LMS2XX_CMD_VALUES + 0x80: return "scan";
    case LMS2XX_CMD_STATUS + 0x80: return "status";
    case LMS2XX_CMD_ERRORS + 0x80: return "errors";
    case LMS2XX_CMD_TYPE + 0x80: return "type";
    case LMS2XX_CMD_VARIANT + 0x80: return "variant reply";
    case LMS2XX_CMD_READ_CONFIG + 0x80: return "config";
    case LMS2XX_CMD_WRITE_CONFIG + 0x80: return "config written";
    default: return "?";
  }
}

const char* lms_mode_name(std::uint8_t m) {
  switch (m) {
    case LMS2XX_MODE_INSTALLATION: return "installation";
    case LMS2XX_MODE_STREAM: return "stream";
    case LMS2XX_MODE_REQUEST: return "on request";
    case LMS2XX_MODE_STREAM_PARTIAL: return "stream partial";
    case LMS2XX_BAUD_38400: return "38400 baud";
    case LMS2XX_BAUD_19200: return "19200 baud";
    case LMS2XX_BAUD_9600: return "9600 baud";
    case LMS2XX_BAUD_500000: return "500000 baud";
    default: return "?";
  }
}

std::uint16_t le16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | p[1] << 8); }

bool lms_crc_ok(const std::uint8_t* t, std::size_t size) {
  return size >= 6 && lms2xx_crc(t, size - 2) == le16(t + size - 2);
}

}  // namespace

bool nmea_checksum_ok(const std::string& s) {
  if (s.empty() || (s[0] != '$' && s[0] != '!')) return false;
  const std::size_t star = s.find('*');
  if (star == std::string::npos || star + 3 != s.size()) return false;
  unsigned sum = 0;
  for (std::size_t i = 1; i < star; ++i) sum ^= static_cast<unsigned char>(s[i]);
  const int hi = hex_digit(s[star + 1]), lo = hex_digit(s[star + 2]);
  return hi >= 0 && lo >= 0 && static_cast<unsigned>(hi * 16 + lo) == sum;
}

std::optional<GeoPoint> nmea_position(const std::string& s) {
  if (s.size() < 7) return std::nullopt;
  const std::string type = s.substr(3, 3);
  const auto f = fields_of(s);
  if (type == "GGA" && f.size() >= 12) {
    if (f[6].empty() || f[6] == "0") return std::nullopt;
    const auto lat = nmea_angle(f[2], f[3]), lon = nmea_angle(f[4], f[5]);
    if (!lat || !lon) return std::nullopt;
    const double alt = f[9].empty() ? NAN : std::atof(f[9].c_str()) + std::atof(f[11].c_str());
    return GeoPoint{*lat, *lon, alt};
  }
  if (type == "RMC" && f.size() >= 7) {
    if (f[2] != "A") return std::nullopt;
    const auto lat = nmea_angle(f[3], f[4]), lon = nmea_angle(f[5], f[6]);
    if (!lat || !lon) return std::nullopt;
    return GeoPoint{*lat, *lon, NAN};
  }
  return std::nullopt;
}

void append_hex(std::string& out, const std::uint8_t* bytes, std::size_t count) {
  static const char digits[] = "0123456789ABCDEF";
  const std::size_t shown = std::min(count, kMaxHexBytes);
  for (std::size_t i = 0; i < shown; ++i) {
    if (!out.empty()) out += ' ';
    out += digits[bytes[i] >> 4];
    out += digits[bytes[i] & 15];
  }
  if (shown < count) out += fmt::format(" .. ({} bytes)", count);
}

std::string lms_summary(const std::uint8_t* t, std::size_t size) {
  if (size < 7) return "short telegram";
  const std::uint8_t cmd = t[4];
  const std::uint8_t* data = t + 5;
  const std::size_t data_len = size - 7;  // between the command and the CRC (a reply's status included)
  std::string s = fmt::format("{:02X} {}", cmd, lms_command_name(cmd));
  if (cmd == LMS2XX_CMD_MODE && data_len >= 1) {
    s += fmt::format(" 0x{:02X} {}", data[0], lms_mode_name(data[0]));
  } else if (cmd == LMS2XX_CMD_VALUES + 0x80 && data_len >= 2) {
    const std::uint16_t w = le16(data);
    s += fmt::format(", {} values, {}", w & LMS2XX_COUNT_MASK, (w >> LMS2XX_UNIT_SHIFT) == 1 ? "mm" : "cm");
    if (w & LMS2XX_PARTIAL_FLAG) s += fmt::format(", partial {}", (w >> LMS2XX_PARTIAL_INDEX_SHIFT) & 3);
  } else if (cmd == LMS2XX_CMD_VARIANT && data_len >= 4) {
    s += fmt::format(" {} deg, {:.2f} deg", le16(data), le16(data + 2) / 100.0);
  } else if (cmd == LMS2XX_CMD_TYPE + 0x80 && data_len >= 2) {
    s += ' ';
    for (std::size_t i = 0; i + 1 < data_len; ++i) append_printable(s, data[i]);
  } else if ((cmd == LMS2XX_CMD_MODE + 0x80) && data_len >= 1) {
    s += data[0] == 0 ? " ok" : fmt::format(" refused ({})", data[0]);
  }
  return s;
}

bool lms_decode_scan(const std::uint8_t* t, std::size_t size, LmsScan& scan) {
  if (size < 10 || t[4] != LMS2XX_CMD_VALUES + 0x80 || !lms_crc_ok(t, size)) return false;
  const std::uint16_t w = le16(t + 5);
  const std::size_t n = w & LMS2XX_COUNT_MASK;
  if (n < 2 || 7 + 2 + 2 * n > size) return false;
  // The variant is not in the telegram; its count tells it: 181 or 361 values span 180 degrees,
  // 101, 201 or 401 span 100 (LMS2xx telegram listing, command 0x3B).
  const double span = (n == 181 || n == 361) ? 180.0 : (n == 101 || n == 201 || n == 401) ? 100.0 : 180.0;
  scan.step_deg = span / static_cast<double>(n - 1);
  scan.start_deg = -span / 2;
  if (w & LMS2XX_PARTIAL_FLAG) scan.start_deg += 0.25 * ((w >> LMS2XX_PARTIAL_INDEX_SHIFT) & 3);
  const double unit_m = (w >> LMS2XX_UNIT_SHIFT) == 1 ? 0.001 : 0.01;
  scan.ranges_m.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    // The 8/80 m modes' 13 bits (the power-up measuring mode); codes at the top mean no echo.
    const unsigned v = le16(t + 7 + 2 * i) & 0x1FFFu;
    scan.ranges_m[i] = v >= 0x1FFFu - LMS2XX_CODE_OVER_RANGE_BELOW_TOP ? NAN : static_cast<float>(v * unit_m);
  }
  return true;
}

UartStream::UartStream(Format format) : format_(format) {
  raw_.reserve(kMaxRawEntry);
  message_.reserve(format == Format::Lms ? LMS2XX_MAX_TELEGRAM : kMaxSentence);
}

void UartStream::resync() {
  raw_.clear();
  message_.clear();
  in_message_ = false;
  hunting_ = format_ != Format::Raw;  // raw bytes have no boundary to wait for
}

void UartStream::reset() {
  raw_.clear();
  message_.clear();
  in_message_ = false;
  hunting_ = false;
  position_.reset();
  altitude_m_ = NAN;
  scan_ = LmsScan{};
}

void UartStream::flush_raw(std::int64_t t_ns, std::vector<LogEntry>& out) {
  if (raw_.empty()) return;
  LogEntry e;
  e.t_ns = t_ns;
  e.kind = LogEntry::Kind::Bytes;
  append_hex(e.hex, raw_.data(), raw_.size());
  out.push_back(std::move(e));
  raw_.clear();
}

void UartStream::feed(const serial_byte* bytes, std::size_t count, std::vector<LogEntry>& out) {
  for (std::size_t i = 0; i < count; ++i) {
    const serial_byte& b = bytes[i];
    switch (format_) {
      case Format::Nmea: nmea_byte(b, out); break;
      case Format::Lms: lms_byte(b, out); break;
      case Format::Raw:
        raw_.push_back(b.value);
        break;
    }
    if (raw_.size() >= kMaxRawEntry) flush_raw(b.end_ns, out);
  }
  if (count) flush_raw(bytes[count - 1].end_ns, out);
}

void UartStream::not_a_sentence(std::int64_t t_ns, std::vector<LogEntry>& out) {
  in_message_ = false;
  for (std::uint8_t v : message_) {
    raw_.push_back(v);
    if (raw_.size() >= kMaxRawEntry) flush_raw(t_ns, out);
  }
}

void UartStream::nmea_byte(const serial_byte& b, std::vector<LogEntry>& out) {
  const char c = static_cast<char>(b.value);
  if (!in_message_) {
    if (c == '$' || c == '!') {
      flush_raw(b.end_ns, out);
      hunting_ = false;
      in_message_ = true;
      message_.assign(1, b.value);
    } else if (c != '\r' && c != '\n' && !hunting_) {
      raw_.push_back(b.value);
    }
    return;
  }
  if (c == '\n' || c == '\r') {
    in_message_ = false;
    LogEntry e;
    e.t_ns = b.end_ns;
    e.kind = LogEntry::Kind::Nmea;
    e.text.assign(message_.begin(), message_.end());
    e.crc_ok = nmea_checksum_ok(e.text) ? 1 : 0;
    if (e.crc_ok) {
      if (auto p = nmea_position(e.text)) {
        if (std::isnan(p->altitude_m)) p->altitude_m = altitude_m_;
        else altitude_m_ = p->altitude_m;
        position_ = p;
      }
    }
    out.push_back(std::move(e));
    return;
  }
  message_.push_back(b.value);
  // Sentences are printable ASCII (NMEA 0183, 5.1.3): a control or high byte (UBX binary that
  // began with a '$', a wrong baud) or a too long line is no sentence; its bytes show as hex.
  if (b.value < 0x20 || b.value >= 0x7F || message_.size() >= kMaxSentence) not_a_sentence(b.end_ns, out);
}

void UartStream::lms_byte(const serial_byte& b, std::vector<LogEntry>& out) {
  if (!in_message_) {
    if (b.value == LMS2XX_STX) {
      flush_raw(b.end_ns, out);
      in_message_ = true;
      message_.assign(1, b.value);
    } else if (hunting_) {
      // Mid-telegram after a resync: an ACK byte here may be scan data.
    } else if (b.value == LMS2XX_ACK || b.value == LMS2XX_NAK) {
      flush_raw(b.end_ns, out);
      LogEntry e;
      e.t_ns = b.end_ns;
      e.kind = LogEntry::Kind::Lms;
      e.text = b.value == LMS2XX_ACK ? "ACK" : "NAK";
      append_hex(e.hex, &b.value, 1);
      out.push_back(std::move(e));
    } else {
      raw_.push_back(b.value);
    }
    return;
  }
  message_.push_back(b.value);
  if (message_.size() < 4) return;
  const std::size_t length = le16(message_.data() + 2);
  const std::size_t total = 4 + length + 2;
  if (length == 0 || total > LMS2XX_MAX_TELEGRAM) {  // an STX in noise, not a telegram
    in_message_ = false;
    if (!hunting_) raw_.insert(raw_.end(), message_.begin(), message_.end());
    return;
  }
  if (message_.size() < total) return;
  in_message_ = false;
  // After a resync the first STX may be a data byte of a telegram under way: only a good CRC
  // says the stream is back in step.
  if (hunting_ && !lms_crc_ok(message_.data(), total)) return;
  hunting_ = false;
  LogEntry e;
  e.t_ns = b.end_ns;
  e.kind = LogEntry::Kind::Lms;
  e.text = lms_summary(message_.data(), total);
  e.crc_ok = lms_crc_ok(message_.data(), total) ? 1 : 0;
  append_hex(e.hex, message_.data(), total);
  if (lms_decode_scan(message_.data(), total, scan_)) scan_.t_ns = b.end_ns;
  out.push_back(std::move(e));
}

}  // namespace sear
