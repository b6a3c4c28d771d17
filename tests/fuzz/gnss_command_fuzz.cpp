// libFuzzer target: any bytes a host sends to the u-blox NEO-6M or MT3339 talker (UBX, PUBX, PMTK or
// noise, at the right baud rate or not) leave both talking well-formed output: time-ordered bytes,
// one frame time apart at least, inside the asked window, every NMEA sentence with a correct
// checksum and at most 82 characters, every UBX frame with a correct Fletcher checksum.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "devices/mtk3339.h"
#include "devices/nmea.h"
#include "devices/ublox_neo6m.h"

namespace {

void still(void*, std::int64_t, gnss_fix_truth* out) {
  *out = gnss_fix_truth{};
  out->latitude_deg = 47.4;
  out->longitude_deg = 8.5;
  out->altitude_msl_m = 500.0;
  out->geoid_separation_m = 48.0;
}

// Checks the output stream: NMEA sentences and UBX frames, nothing else once in sync.
struct Checker {
  std::vector<std::uint8_t> pending;
  void add(const serial_byte* b, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) pending.push_back(b[i].value);
    for (;;) {
      if (pending.empty()) return;
      if (pending[0] == '$') {
        std::size_t end = 0;
        for (std::size_t i = 1; i < pending.size(); ++i)
          if (pending[i] == '\n') {
            end = i + 1;
            break;
          }
        if (end == 0) {
          if (pending.size() > NMEA_MAX_SENTENCE) __builtin_trap();
          return;
        }
        if (end > NMEA_MAX_SENTENCE) __builtin_trap();
        const char* body;
        std::size_t len;
        if (!nmea_parse_frame(reinterpret_cast<const char*>(pending.data()), end, &body, &len)) __builtin_trap();
        pending.erase(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(end));
      } else if (pending[0] == 0xB5) {
        if (pending.size() < 8) return;
        const std::size_t len = pending[4] | static_cast<std::size_t>(pending[5]) << 8;
        if (pending[1] != 0x62 || len > UBLOX_MAX_OUT_PAYLOAD) __builtin_trap();
        if (pending.size() < len + 8) return;
        std::uint8_t frame[UBLOX_MAX_OUT_PAYLOAD + 8];
        ubx_frame(pending[2], pending[3], pending.data() + 6, static_cast<std::uint16_t>(len), frame);
        if (std::memcmp(frame, pending.data(), len + 8) != 0) __builtin_trap();
        pending.erase(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(len + 8));
      } else {
        __builtin_trap();  // a talker never sends anything but sentences and UBX frames
      }
    }
  }
};

void check_times(const serial_byte* out, std::size_t n, std::int64_t& last_end, std::int64_t until) {
  for (std::size_t i = 0; i < n; ++i) {
    if (out[i].end_ns >= until) __builtin_trap();
    if (out[i].end_ns - serial_frame_ns(out[i].baud) < last_end) __builtin_trap();  // overlapping frames
    if (out[i].baud < 4800 || out[i].baud > 115200) __builtin_trap();
    last_end = out[i].end_ns;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const gnss_truth_source src{still, nullptr};
  static ublox_neo6m u;  // large: keep off the stack
  static mtk3339 m;
  ublox_neo6m_config uc;
  ublox_neo6m_defaults(&uc);
  uc.error.ttff_s = 1.0;
  uc.error.correlation_s = 1.0;  // short moving-sum window keeps each run fast
  ublox_neo6m_init(&u, &uc, src, 0);
  mtk3339_config mc;
  mtk3339_defaults(&mc);
  mc.error.ttff_s = 1.0;
  mc.error.correlation_s = 1.0;
  mtk3339_init(&m, &mc, src, 0);

  Checker cu, cm;
  std::int64_t t = 0, drained = 0, last_u = INT64_MIN, last_m = INT64_MIN;
  static serial_byte out[256];
  // Drains both talkers up to `until` in windows that follow each other, as the lockstep does.
  auto drain = [&](std::int64_t until) {
    if (until <= drained) return;
    std::size_t n;
    do {
      n = ublox_neo6m_transmit(&u, drained, until, out, 256);
      check_times(out, n, last_u, until);
      cu.add(out, n);
    } while (n == 256);
    do {
      n = mtk3339_transmit(&m, drained, until, out, 256);
      check_times(out, n, last_m, until);
      cm.add(out, n);
    } while (n == 256);
    drained = until;
  };
  for (std::size_t i = 0; i < size; ++i) {
    // A control byte 0xFF followed by d lets d * 10 ms pass without host bytes.
    if (data[i] == 0xFF && i + 1 < size) {
      t += (data[++i] + 1) * INT64_C(10000000);
      drain(t);
      continue;
    }
    serial_byte b{};
    b.value = data[i];
    b.baud = ublox_neo6m_baud(&u);
    b.end_ns = t + serial_frame_ns(b.baud);
    ublox_neo6m_receive(&u, &b);
    b.baud = mtk3339_baud(&m);
    mtk3339_receive(&m, &b);
    t = b.end_ns;
    drain(t);
  }
  drain(t + 2 * INT64_C(1000000000));
  return 0;
}
