// libFuzzer target: whatever a host sends, the LMS2xx model answers only with ACK/NAK bytes and
// whole telegrams from 0x80 with a correct CRC, one rate per telegram, never two bytes at once.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "devices/sick_lms2xx.h"

namespace {

constexpr int64_t kMs = 1000000;

// Ranges that test the encoder's edges: nothing, NaN, negative, huge, and a plain wall.
void measure(void* context, int64_t, double first_rad, double step_rad, uint32_t count, double* out_m) {
  const uint8_t kind = *static_cast<const uint8_t*>(context);
  for (uint32_t i = 0; i < count; ++i) {
    const double theta = first_rad + step_rad * i;
    switch ((kind + i) % 6) {
      case 0: out_m[i] = std::numeric_limits<double>::infinity(); break;
      case 1: out_m[i] = std::nan(""); break;
      case 2: out_m[i] = -1.0; break;
      case 3: out_m[i] = 1e300; break;
      default: out_m[i] = 2.0 / std::fabs(std::sin(theta) + 1e-3); break;
    }
  }
}

bool known_rate(uint32_t baud) { return baud == 9600 || baud == 19200 || baud == 38400 || baud == 500000; }

void check(const std::vector<serial_byte>& line) {
  for (size_t i = 0; i < line.size(); ++i) {
    if (!known_rate(line[i].baud)) __builtin_trap();
    // A byte may not begin before the one before it has ended.
    if (i && line[i].end_ns - line[i - 1].end_ns < serial_frame_ns(line[i].baud)) __builtin_trap();
  }
  size_t i = 0;
  while (i < line.size()) {
    const uint8_t v = line[i].value;
    if (v == LMS2XX_ACK || v == LMS2XX_NAK) {
      ++i;
      continue;
    }
    if (v != LMS2XX_STX) __builtin_trap();
    if (line.size() - i < 4) return;  // still on the line when the run ended
    if (line[i + 1].value != LMS2XX_REPLY_ADDRESS) __builtin_trap();
    const size_t total = 4 + (line[i + 2].value | (line[i + 3].value << 8)) + 2u;
    if (total > LMS2XX_MAX_TELEGRAM || total < 8) __builtin_trap();
    if (line.size() - i < total) return;
    uint8_t t[LMS2XX_MAX_TELEGRAM];
    for (size_t k = 0; k < total; ++k) {
      t[k] = line[i + k].value;
      if (line[i + k].baud != line[i].baud) __builtin_trap();
    }
    const uint16_t crc = lms2xx_crc(t, total - 2);
    if (t[total - 2] != (crc & 0xFF) || t[total - 1] != (crc >> 8)) __builtin_trap();
    if (t[total - 3] != LMS2XX_STATUS_OK) __builtin_trap();
    i += total;
  }
}

}  // namespace

// Input: byte 0 picks the scan source, units (bit 0), measuring mode (bits 1-3), the 100/0.25
// variant (bit 4), a 300 ms pause after every 0x08 host byte (bit 6: replies and streams get
// time to run) and every 7th host byte sent at 9600 whatever the receiver listens at (bit 7:
// framing errors). The rest are host bytes, back to back at the receiver's rate.
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  uint8_t kind = data[0];
  lms2xx_config c;
  lms2xx_default_config(&c);
  c.power_up_ns = 10 * kMs;
  c.seed = kind;
  c.units = kind & 1;
  c.measuring_mode = static_cast<uint8_t>((kind >> 1) & 7);
  if (kind & 0x10) {
    c.scan_angle_deg = 100;
    c.resolution_cdeg = 25;
  }
  static lms2xx dev;  // about 5 kB: kept off the stack
  lms2xx_init(&dev, &c, lms2xx_scan_source{measure, &kind}, 0);
  std::vector<serial_byte> line;
  serial_byte buf[64];
  int64_t now = 20 * kMs;
  auto run_until = [&](int64_t t) {
    while (now < t && line.size() < 200000) {
      const int64_t next = std::min(now + kMs, t);
      size_t n;
      do {
        n = lms2xx_transmit(&dev, now, next, buf, 64);
        line.insert(line.end(), buf, buf + n);
      } while (n == 64);
      now = next;
    }
  };
  run_until(now);
  for (size_t i = 1; i < size; ++i) {
    const uint32_t rate = (kind & 0x80) && (i % 7 == 0) ? 9600u : lms2xx_baud(&dev);
    const int64_t end = now + serial_frame_ns(rate);
    run_until(end);
    const serial_byte b{end, rate, data[i], {0, 0, 0}};
    lms2xx_receive(&dev, &b);
    if ((kind & 0x40) && data[i] == 0x08) run_until(now + 300 * kMs);  // a pause after some bytes
  }
  run_until(now + 2000 * kMs);
  check(line);
  return 0;
}
