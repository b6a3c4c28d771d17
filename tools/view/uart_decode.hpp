// UART traffic as the viewer shows it: NMEA 0183 sentences (checksum checked), SICK LMS2xx
// telegrams (CRC checked, summarised, scans decoded), anything else as hex; and the position a GPS
// sentence gives.
#pragma once

#include <cstdint>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "devices/serial_byte.h"
#include "scene/geodetic.hpp"
#include "view/mcu_panel_log.hpp"

namespace sear {

// "$...*HH": true when the two hex digits after '*' are the XOR of every character between '$'
// (or '!') and '*' (NMEA 0183, section 5.2.1). False when there is no checksum.
bool nmea_checksum_ok(const std::string& sentence);

// The position of a GGA (fix quality > 0) or RMC (status A) sentence; GGA's altitude is above the
// ellipsoid (MSL + geoid separation), RMC's is NaN (it carries none).
std::optional<GeoPoint> nmea_position(const std::string& sentence);

// One line of "02 80 ..." text, at most kMaxHexBytes bytes shown, then " .. (N bytes)".
constexpr std::size_t kMaxHexBytes = 48;
void append_hex(std::string& out, const std::uint8_t* bytes, std::size_t count);

// What an LMS2xx telegram (STX .. CRC) is: "B0 scan, 361 values, mm", "20 mode 0x24 stream", ...
std::string lms_summary(const std::uint8_t* telegram, std::size_t size);

// A scan decoded from a 0xB0 telegram: angles in the mount frame (degrees counter-clockwise from
// the scanner's straight ahead), NaN where no echo came back.
struct LmsScan {
  std::int64_t t_ns = -1;  // -1: none yet
  double start_deg = 0;
  double step_deg = 0;
  std::vector<float> ranges_m;
};
// False unless `telegram` is a whole 0xB0 telegram with a good CRC.
bool lms_decode_scan(const std::uint8_t* telegram, std::size_t size, LmsScan& scan);

// The bytes one way on one UART device's line, cut into log entries as they arrive.
class UartStream {
 public:
  enum class Format { Nmea, Lms, Raw };
  explicit UartStream(Format format);
  // Appends the messages these bytes complete to `out` (their mcu, device and direction are left
  // for the caller); bytes that are no message go out as one "bytes" entry per call.
  void feed(const serial_byte* bytes, std::size_t count, std::vector<LogEntry>& out);
  void reset();
  // Bytes were missed (nobody watched): nothing is logged until the next message starts (a '$'
  // or '!', or an LMS2xx telegram with a good CRC), so that no torn one shows.
  void resync();

  // The newest decoded values: a GPS's position (from sentences with good checksums) and an LMS's scan.
  const std::optional<GeoPoint>& last_position() const { return position_; }
  const LmsScan& last_scan() const { return scan_; }

 private:
  void flush_raw(std::int64_t t_ns, std::vector<LogEntry>& out);
  void not_a_sentence(std::int64_t t_ns, std::vector<LogEntry>& out);
  void nmea_byte(const serial_byte& b, std::vector<LogEntry>& out);
  void lms_byte(const serial_byte& b, std::vector<LogEntry>& out);

  Format format_;
  std::vector<std::uint8_t> raw_;      // bytes that are not (yet) a message
  std::vector<std::uint8_t> message_;  // the message under way
  bool in_message_ = false;
  bool hunting_ = false;  // after resync(): waiting for a message boundary
  std::optional<GeoPoint> position_;
  double altitude_m_ = NAN;  // the latest GGA's, for RMC positions
  LmsScan scan_;
};

}  // namespace sear
