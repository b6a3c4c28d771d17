// SICK LMS2xx device model against SICK's telegram listing ("Telegrams for Configuring and
// Operating the LMS2xx Laser Measurement Systems", 8007954) and the request sequences of open host
// drivers (sicktoolbox SickLMS2xx::Initialize / _setSickConfig, Player's sicklms200 driver).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "devices/sick_lms2xx.h"

namespace {

constexpr int64_t kMs = 1000000;
constexpr int64_t kS = 1000000000;
constexpr double kDeg = M_PI / 180.0;
// One mirror sweep at 75 Hz, as the model numbers them.
constexpr int64_t kSweepNs = 40000000 / 3;

// Walls seen from the scanner: each is the line at perpendicular distance d whose foot lies at
// angle phi (scanner convention). A ray at theta meets it at d / cos(theta - phi) when it points
// towards it; the scene's range is the nearest wall.
struct Wall {
  double d_m, phi_rad;
};

struct Scene {
  std::vector<Wall> walls;
  struct Call {
    int64_t time_ns;
    double first_rad, step_rad;
    uint32_t count;
  };
  std::vector<Call> calls;

  double range(double theta) const {
    double r = std::numeric_limits<double>::infinity();
    for (const Wall& w : walls) {
      const double c = std::cos(theta - w.phi_rad);
      if (c > 1e-12) r = std::min(r, w.d_m / c);
    }
    return r;
  }
  // When set, walls move out 1 mm per sweep (modulo 1 m), so a value tells its sweep.
  bool sweep_coded = false;
  static int64_t sweep_of(int64_t time_ns) { return (time_ns * 3 + 20000000) / 40000000; }

  static void measure(void* context, int64_t time_ns, double first_rad, double step_rad, uint32_t count,
                      double* out_m) {
    auto* scene = static_cast<Scene*>(context);
    scene->calls.push_back({time_ns, first_rad, step_rad, count});
    const double shift = scene->sweep_coded ? 0.001 * static_cast<double>(sweep_of(time_ns) % 1000) : 0.0;
    for (uint32_t i = 0; i < count; ++i) out_m[i] = scene->range(first_rad + step_rad * i) + shift;
  }
};

// A telegram (or a lone ACK/NAK) as it came off the line.
struct Item {
  std::vector<uint8_t> bytes;
  int64_t first_end_ns, last_end_ns;
  uint32_t baud;
  uint8_t code() const { return bytes.size() == 1 ? bytes[0] : bytes[4]; }
  // Reply code, data and status, as drivers hand it on ("payload").
  std::vector<uint8_t> payload() const { return {bytes.begin() + 4, bytes.end() - 2}; }
  int64_t start_ns() const { return first_end_ns - serial_frame_ns(baud); }
};

// The host end of the line: drives the model in 1 ms quanta, as the lockstep bridge does, and
// splits what comes back into ACK/NAK bytes and telegrams (checking address, length and CRC).
struct Host {
  lms2xx dev{};
  Scene scene;
  int64_t now = 0;
  std::vector<serial_byte> line;
  size_t parsed = 0;

  explicit Host(lms2xx_config c, int64_t power_on_ns = 0) {
    now = power_on_ns;
    lms2xx_init(&dev, &c, lms2xx_scan_source{&Scene::measure, &scene}, power_on_ns);
  }
  static lms2xx_config quick_config() {
    lms2xx_config c;
    lms2xx_default_config(&c);
    c.power_up_ns = 100 * kMs;
    c.noise_sd_cm_mode_m = 0.0;
    c.noise_sd_mm_mode_m = 0.0;
    return c;
  }

  void run_until(int64_t t) {
    while (now < t) {
      const int64_t next = std::min(now + kMs, t);
      serial_byte buf[16];
      size_t n;
      do {  // a small cap, so that bytes left over by it are exercised
        n = lms2xx_transmit(&dev, now, next, buf, 16);
        line.insert(line.end(), buf, buf + n);
      } while (n == 16);
      now = next;
    }
  }
  void run_for(int64_t dt) { run_until(now + dt); }

  // Sends bytes back to back from `now` at `baud`; returns the end of the last one.
  int64_t send_raw(const std::vector<uint8_t>& bytes, uint32_t baud) {
    for (uint8_t v : bytes) {
      const int64_t end = now + serial_frame_ns(baud);
      run_until(end);
      serial_byte b{end, baud, v, {0, 0, 0}};
      lms2xx_receive(&dev, &b);
    }
    return now;
  }
  int64_t send(const std::vector<uint8_t>& payload, uint32_t baud) {
    uint8_t t[300];
    const size_t n = lms2xx_encode_request(payload.data(), payload.size(), t, sizeof t);
    EXPECT_GT(n, 0u);
    return send_raw(std::vector<uint8_t>(t, t + n), baud);
  }

  // Everything that came since the last call, split into items.
  std::vector<Item> take() {
    std::vector<Item> items;
    while (parsed < line.size()) {
      const serial_byte& b = line[parsed];
      if (b.value == LMS2XX_ACK || b.value == LMS2XX_NAK) {
        items.push_back({{b.value}, b.end_ns, b.end_ns, b.baud});
        ++parsed;
        continue;
      }
      EXPECT_EQ(b.value, LMS2XX_STX) << "stray byte at " << parsed;
      if (line.size() - parsed < 4) break;
      const size_t len = line[parsed + 2].value | (line[parsed + 3].value << 8);
      const size_t total = 4 + len + 2;
      if (line.size() - parsed < total) break;  // still on the line
      Item it{{}, b.end_ns, line[parsed + total - 1].end_ns, b.baud};
      for (size_t i = 0; i < total; ++i) {
        it.bytes.push_back(line[parsed + i].value);
        EXPECT_EQ(line[parsed + i].baud, b.baud) << "a telegram changed rate mid-way";
      }
      EXPECT_EQ(it.bytes[1], LMS2XX_REPLY_ADDRESS);
      const uint16_t crc = lms2xx_crc(it.bytes.data(), total - 2);
      EXPECT_EQ(it.bytes[total - 2], crc & 0xFF);
      EXPECT_EQ(it.bytes[total - 1], crc >> 8);
      EXPECT_EQ(it.bytes[total - 3], LMS2XX_STATUS_OK);
      items.push_back(it);
      parsed += total;
    }
    return items;
  }

  // A request, then the ACK and exactly one reply, which is returned (host drivers wait up to
  // 1 s for it, sicktoolbox's DEFAULT_SICK_LMS_2XX_SICK_MESSAGE_TIMEOUT).
  Item transact(const std::vector<uint8_t>& payload, uint32_t baud, int64_t wait = 1 * kS) {
    take();
    const int64_t request_end = send(payload, baud);
    run_for(wait);
    // Scans streaming meanwhile are not part of the exchange (unless scans were asked for).
    std::vector<Item> items;
    bool line_was_busy = false;
    for (const Item& it : take()) {
      if (it.bytes.size() > 1 && it.code() == 0xB0 && payload[0] != LMS2XX_CMD_VALUES) {
        line_was_busy |= items.empty() && it.last_end_ns > request_end;
        continue;
      }
      items.push_back(it);
    }
    EXPECT_EQ(items.size(), 2u) << "request 0x" << std::hex << int(payload[0]);
    if (items.size() < 2) return {};
    EXPECT_EQ(items[0].code(), LMS2XX_ACK);
    // The ACK comes LMS2XX_ACK_DELAY_NS after the request, or once a telegram already on the
    // line has ended; Player waits 1 s for it at most.
    EXPECT_GE(items[0].start_ns() - request_end, LMS2XX_ACK_DELAY_NS);
    if (!line_was_busy) {
      EXPECT_EQ(items[0].start_ns() - request_end, LMS2XX_ACK_DELAY_NS);
    }
    EXPECT_EQ(items[0].baud, baud);
    EXPECT_EQ(items[1].code(), payload[0] | 0x80);
    EXPECT_EQ(items[1].baud, baud);
    EXPECT_GT(items[1].start_ns(), items[0].start_ns());
    return items[1];
  }

  void power_up() {
    run_for(dev.config.power_up_ns + 50 * kMs);  // the 20-byte message takes 20.8 ms at 9600
    const auto items = take();
    ASSERT_EQ(items.size(), 1u);
    ASSERT_EQ(items[0].code(), LMS2XX_REPLY_POWER_ON);
  }

  // The 0xB0 telegrams of a stream, over `dt`.
  std::vector<Item> scans_over(int64_t dt) {
    take();
    run_for(dt);
    std::vector<Item> scans;
    for (const Item& it : take())
      if (it.bytes.size() > 1 && it.code() == 0xB0) scans.push_back(it);
    return scans;
  }
};

uint16_t word_at(const std::vector<uint8_t>& p, size_t i) { return static_cast<uint16_t>(p[i] | (p[i + 1] << 8)); }

// The mode-change success reply, as the listing gives it and as some drivers compare it.
const std::vector<uint8_t> kModeChangeOk = {0x02, 0x80, 0x03, 0x00, 0xA0, 0x00, 0x10, 0x16, 0x0A};

// Measured values of a 0xB0 payload (code, count word, values, status).
std::vector<uint16_t> values_of(const Item& it) {
  const auto p = it.payload();
  const size_t n = word_at(p, 1) & LMS2XX_COUNT_MASK;
  EXPECT_EQ(p.size(), 1 + 2 + 2 * n + 1);
  std::vector<uint16_t> v;
  for (size_t i = 0; i < n; ++i) v.push_back(word_at(p, 3 + 2 * i));
  return v;
}

TEST(Lms2xxCrc, MatchesTheListingsVectors) {
  // Request "change to continuous output" 02 00 02 00 20 24 carries CRC bytes 34 08, and the
  // mode-change success reply 02 80 03 00 A0 00 10 carries 16 0A (telegram listing examples).
  const uint8_t request[] = {0x02, 0x00, 0x02, 0x00, 0x20, 0x24};
  EXPECT_EQ(lms2xx_crc(request, sizeof request), 0x0834);
  EXPECT_EQ(lms2xx_crc(kModeChangeOk.data(), 7), 0x0A16);

  const uint8_t payload[] = {0x20, 0x24};
  uint8_t out[16];
  ASSERT_EQ(lms2xx_encode_request(payload, 2, out, sizeof out), 8u);
  EXPECT_EQ(std::vector<uint8_t>(out, out + 8), (std::vector<uint8_t>{0x02, 0x00, 0x02, 0x00, 0x20, 0x24, 0x34, 0x08}));
  EXPECT_EQ(lms2xx_encode_request(payload, 2, out, 7), 0u);
}

// sicktoolbox SickLMS2xx::Initialize(SICK_BAUD_38400), then SetSickVariant(100, 0.25),
// SetSickMeasuringUnits(mm) (which goes through installation mode, 0x77 and back), and the
// data stream, each request written out from reading the driver, each reply checked as the driver
// checks it.
TEST(Lms2xxProtocol, AnswersSicktoolboxInitialisation) {
  lms2xx_config c = Host::quick_config();
  c.power_up_ns = LMS2XX_DEFAULT_POWER_UP_NS;
  Host h(c, 3 * kS);
  h.scene.walls = {{3.0, 90 * kDeg}};

  // While the scanner boots it does not listen: a request right after power-on gets nothing.
  h.send({0x31}, 9600);
  h.run_until(3 * kS + LMS2XX_DEFAULT_POWER_UP_NS - kMs);
  EXPECT_TRUE(h.take().empty());
  // Then the power-on message, at the power-up rate of 9600 baud (20 bytes, 20.8 ms).
  h.run_for(50 * kMs);
  auto items = h.take();
  ASSERT_EQ(items.size(), 1u);
  EXPECT_EQ(items[0].code(), LMS2XX_REPLY_POWER_ON);
  EXPECT_EQ(items[0].baud, 9600u);
  EXPECT_EQ(items[0].start_ns(), 3 * kS + LMS2XX_DEFAULT_POWER_UP_NS);

  // _setSessionBaud(SICK_BAUD_38400): 0x20 0x40, answered at 9600, then the link runs at 38400.
  Item r = h.transact({0x20, 0x40}, 9600);
  EXPECT_EQ(r.bytes, kModeChangeOk);
  EXPECT_EQ(lms2xx_baud(&h.dev), 38400u);
  h.run_for(250 * kMs);  // "Sick likes a sleep here"

  // _setSickOpModeMonitorRequestValues: 0x20 0x25; the driver checks payload[1] == 0.
  r = h.transact({0x20, 0x25}, 38400);
  EXPECT_EQ(r.bytes, kModeChangeOk);

  // _getSickType: 0x3A; the driver searches the payload for "LMS200;30106".
  r = h.transact({0x3A}, 38400);
  const auto type = r.payload();
  EXPECT_EQ(std::string(type.begin() + 1, type.end() - 1), "LMS200;30106");

  // _getSickStatus: 0x31; operating mode at [8], status at [9], measuring mode [102], scan
  // angle [107], resolution [109], units [122], as sicktoolbox reads them.
  r = h.transact({0x31}, 38400);
  auto st = r.payload();
  ASSERT_EQ(st.size(), 1u + LMS2XX_STATUS_BYTES + 1u);
  EXPECT_EQ(st[8], 0x25);
  EXPECT_EQ(st[9], 0x00);
  EXPECT_EQ(st[102], LMS2XX_MEAS_8_80M_FA_FB_DAZZLE);
  EXPECT_EQ(word_at(st, 107), 180);
  EXPECT_EQ(word_at(st, 109), 50);
  EXPECT_EQ(st[122], LMS2XX_UNITS_CM);

  // _getSickConfig: 0x74; 34 bytes of blocks A..A4, measuring mode at [5], units at [6].
  r = h.transact({0x74}, 38400);
  auto cfg = r.payload();
  ASSERT_EQ(cfg.size(), 1u + LMS2XX_CONFIG_BYTES + 1u);
  EXPECT_EQ(cfg[1 + 5], LMS2XX_MEAS_8_80M_FA_FB_DAZZLE);
  EXPECT_EQ(cfg[1 + 6], LMS2XX_UNITS_CM);

  // _setSickVariant(100 degrees, 25 = 0.25 degree): 0x3B 64 00 19 00; accepted when [1] == 1.
  r = h.transact({0x3B, 0x64, 0x00, 0x19, 0x00}, 38400);
  EXPECT_EQ(r.payload(), (std::vector<uint8_t>{0xBB, 0x01, 0x64, 0x00, 0x19, 0x00, 0x10}));
  // A variant the LMS has not (180 degrees at 0.25) is refused and the old one kept.
  r = h.transact({0x3B, 0xB4, 0x00, 0x19, 0x00}, 38400);
  EXPECT_EQ(r.payload(), (std::vector<uint8_t>{0xBB, 0x00, 0x64, 0x00, 0x19, 0x00, 0x10}));

  // _setSickConfig: a 0x77 outside installation mode is refused ([1] = 0) ...
  std::vector<uint8_t> write = {0x77};
  write.insert(write.end(), cfg.begin() + 1, cfg.begin() + 1 + LMS2XX_CONFIG_BYTES);
  write[1 + 6] = LMS2XX_UNITS_MM;
  r = h.transact(write, 38400);
  EXPECT_EQ(r.payload()[1], 0x00);
  // ... a wrong password gets 0xA0 with answer 1 ...
  r = h.transact({0x20, 0x00, 'S', 'I', 'C', 'K', '_', 'L', 'M', 'X'}, 38400);
  EXPECT_EQ(r.payload()[1], 0x01);
  // ... _setSickOpModeInstallation with "SICK_LMS" succeeds, then the write does.
  r = h.transact({0x20, 0x00, 'S', 'I', 'C', 'K', '_', 'L', 'M', 'S'}, 38400);
  EXPECT_EQ(r.bytes, kModeChangeOk);
  r = h.transact(write, 38400, 2 * kS);
  auto written = r.payload();
  ASSERT_EQ(written.size(), 1u + 1u + LMS2XX_CONFIG_BYTES + 1u);
  EXPECT_EQ(written[1], 0x01);
  EXPECT_EQ(written[2 + 6], LMS2XX_UNITS_MM);
  r = h.transact({0x20, 0x25}, 38400);
  EXPECT_EQ(r.bytes, kModeChangeOk);
  st = h.transact({0x31}, 38400).payload();
  EXPECT_EQ(st[122], LMS2XX_UNITS_MM);
  EXPECT_EQ(word_at(st, 107), 100);
  EXPECT_EQ(word_at(st, 109), 25);
  // _getSickErrors (its baud probe): 0x32 with no errors is just the code and the status.
  EXPECT_EQ(h.transact({0x32}, 38400).payload(), (std::vector<uint8_t>{0xB2, 0x10}));

  // _setSickOpModeMonitorStreamValues: 0x20 0x24, then 0xB0 telegrams of 401 values in mm.
  r = h.transact({0x20, 0x24}, 38400);
  EXPECT_EQ(r.bytes, kModeChangeOk);
  const auto scans = h.scans_over(2 * kS);
  ASSERT_GE(scans.size(), 2u);
  const auto p = scans[0].payload();
  EXPECT_EQ(word_at(p, 1), 401u | (LMS2XX_UNITS_MM << LMS2XX_UNIT_SHIFT));
  EXPECT_EQ(scans[0].bytes.size(), 4u + 1u + 2u + 802u + 1u + 2u);
  EXPECT_EQ(values_of(scans[0])[200], 3000);  // straight ahead (90 degrees) the wall is 3 m off
}

// Player's sicklms200 driver: installation mode, type, configuration read-modify-write (it
// sends back the 0xF4 payload as 0x77), variant 180/0.5, then 0x20 0x24 waiting for the ACK.
TEST(Lms2xxProtocol, AnswersPlayersSicklms200Setup) {
  Host h(Host::quick_config());
  h.power_up();
  Item r = h.transact({0x20, 0x00, 0x53, 0x49, 0x43, 0x4B, 0x5F, 0x4C, 0x4D, 0x53}, 9600);
  EXPECT_EQ(r.bytes, kModeChangeOk);
  EXPECT_EQ(h.transact({0x3A}, 9600).code(), 0xBA);
  auto f4 = h.transact({0x74}, 9600).payload();
  f4.pop_back();  // ReadFromLaser drops the status byte
  f4[0] = 0x77;
  f4[6] = 0x00;  // no intensity bits
  f4[7] = 0x01;  // range_res 1 -> mm
  r = h.transact(f4, 9600, 2 * kS);
  EXPECT_EQ(r.code(), 0xF7);
  EXPECT_EQ(h.transact({0x3B, 0xB4, 0x00, 0x32, 0x00}, 9600).payload()[1], 0x01);
  r = h.transact({0x20, 0x24}, 9600);
  EXPECT_EQ(r.bytes, kModeChangeOk);
  // Player reads the count as raw[1] | (raw[2] & 0x3F) << 8 and units as raw[2] >> 6.
  const auto scans = h.scans_over(2 * kS);
  ASSERT_FALSE(scans.empty());
  const auto p = scans[0].payload();
  EXPECT_EQ(p[1] | ((p[2] & 0x3F) << 8), 361);
  EXPECT_EQ(p[2] >> 6, 1);
}

TEST(Lms2xxProtocol, NaksBadTelegramsAndResynchronises) {
  Host h(Host::quick_config());
  h.power_up();
  // Line noise between telegrams is ignored.
  h.send_raw({0xFF, 0x13, 0x00, 0x80, 0x55}, 9600);
  h.run_for(50 * kMs);
  EXPECT_TRUE(h.take().empty());
  // A telegram with a wrong CRC is refused with NAK, and nothing else.
  const int64_t end = h.send_raw({0x02, 0x00, 0x01, 0x00, 0x31, 0x12, 0x34}, 9600);
  h.run_for(200 * kMs);
  auto items = h.take();
  ASSERT_EQ(items.size(), 1u);
  EXPECT_EQ(items[0].code(), LMS2XX_NAK);
  EXPECT_EQ(items[0].start_ns() - end, LMS2XX_ACK_DELAY_NS);
  // A stray STX right before a good telegram: the header it starts is rejected and the receiver
  // finds the real telegram's STX among the bytes it had taken for that header.
  uint8_t t[16];
  const uint8_t status[] = {0x31};
  const size_t n = lms2xx_encode_request(status, 1, t, sizeof t);
  // A status request behind `garbage`, and what comes back within half a second.
  const auto status_request_after = [&](std::vector<uint8_t> garbage) {
    garbage.insert(garbage.end(), t, t + n);
    h.send_raw(garbage, 9600);
    h.run_for(500 * kMs);
    return h.take();
  };
  items = status_request_after({0x02});
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0].code(), LMS2XX_ACK);
  EXPECT_EQ(items[1].code(), 0xB1);
  // A truncated header whose announced length swallows the next telegram: its "CRC" fails
  // (NAK), the receiver re-reads from the byte after its STX, takes the real STX's header with
  // two bytes too many (a second NAK), and on the next try finds the real telegram.
  items = status_request_after({0x02, 0x00, 0x02, 0x00});
  ASSERT_EQ(items.size(), 4u);
  EXPECT_EQ(items[0].code(), LMS2XX_NAK);
  EXPECT_EQ(items[1].code(), LMS2XX_NAK);
  EXPECT_EQ(items[2].code(), LMS2XX_ACK);
  EXPECT_EQ(items[3].code(), 0xB1);
  // Telegrams for another address (here a reply echoed back) and unknown commands.
  std::vector<uint8_t> echo = kModeChangeOk;
  h.send_raw(echo, 9600);
  h.run_for(100 * kMs);
  EXPECT_TRUE(h.take().empty());
  // And the receiver is in step again.
  EXPECT_EQ(h.transact({0x31}, 9600).code(), 0xB1);
}

// Unknown commands are acknowledged (the CRC was right) and answered 0x92, "not recognised".
TEST(Lms2xxProtocol, AnswersUnknownCommandsWithNotRecognised) {
  Host h(Host::quick_config());
  h.power_up();
  h.send({0x99}, 9600);
  h.run_for(100 * kMs);
  const auto items = h.take();
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0].code(), LMS2XX_ACK);
  EXPECT_EQ(items[1].payload(), (std::vector<uint8_t>{LMS2XX_REPLY_NOT_RECOGNISED, 0x10}));
}

TEST(Lms2xxProtocol, BaudChangeIsAnsweredAtTheOldRateThenTakesEffect) {
  Host h(Host::quick_config());
  h.power_up();
  EXPECT_EQ(lms2xx_baud(&h.dev), 9600u);
  const Item r = h.transact({0x20, 0x48}, 9600);
  EXPECT_EQ(r.bytes, kModeChangeOk);
  EXPECT_EQ(r.baud, 9600u);
  EXPECT_EQ(lms2xx_baud(&h.dev), 500000u);
  // The old rate now reads as framing errors: no answer at all.
  h.send({0x31}, 9600);
  h.run_for(100 * kMs);
  EXPECT_TRUE(h.take().empty());
  EXPECT_EQ(h.transact({0x31}, 500000).baud, 500000u);
  // Every rate the LMS has, there and back.
  const struct {
    uint8_t code;
    uint32_t baud;
  } rates[] = {{0x41, 19200}, {0x40, 38400}, {0x42, 9600}};
  uint32_t old = 500000;
  for (const auto& rate : rates) {
    EXPECT_EQ(h.transact({0x20, rate.code}, old).baud, old);
    EXPECT_EQ(lms2xx_baud(&h.dev), rate.baud);
    old = rate.baud;
  }
}

// The status reply (0xB1) carries the current rate's code where sicktoolbox reads the baud word
// (payload bytes 116-117, low byte first): the listing's 0x8019 at 38400, and the same reload
// arithmetic (0x8000 | (16 MHz / (16 x rate) - 1)) at the others; the permanent-rate flag (119)
// is 0, as a 0x20 change holds only until power-off.
TEST(Lms2xxProtocol, StatusCarriesTheCurrentRatesBaudWord) {
  Host h(Host::quick_config());
  h.power_up();
  EXPECT_EQ(word_at(h.transact({0x31}, 9600).payload(), 116), 0x8067);
  const struct {
    uint8_t code;
    uint32_t baud;
    uint16_t word;
  } rates[] = {{0x40, 38400, 0x8019}, {0x41, 19200, 0x8033}, {0x48, 500000, 0x8001}, {0x42, 9600, 0x8067}};
  uint32_t old = 9600;
  for (const auto& r : rates) {
    h.transact({0x20, r.code}, old);
    const auto p = h.transact({0x31}, r.baud).payload();
    ASSERT_EQ(p.size(), 1u + LMS2XX_STATUS_BYTES + 1u);
    EXPECT_EQ(word_at(p, 116), r.word) << r.baud;
    EXPECT_EQ(word_at(p, 116), 0x8000 + (16000000 / (16 * r.baud) - 1)) << r.baud;
    EXPECT_EQ(p[119], 0) << r.baud;
    old = r.baud;
  }
}

// Polled scans (0x30 01 in mode 0x25, as sicktoolbox's GetSickScan and Player poll) are each a
// scan not sent before: a host that polls as fast as the line allows gets the mirror's scan rate,
// 75 Hz over the sweeps one scan interlaces: 75 at 1 degree, 37.5 at 0.5, 18.75 at 100 deg /
// 0.25 deg (the listing's scan times 13.33 / 26.67 / 53.33 ms), never the same scan twice. At
// 500 kBd the line is never the limit: 401 values are 812 bytes, 16.2 ms.
TEST(Lms2xxScan, PollingGetsEachScanOnceAtTheMirrorsRate) {
  const struct {
    uint16_t angle, res_cdeg;
    double scans_per_s;
  } variants[] = {{180, 100, 75.0}, {180, 50, 37.5}, {100, 25, 18.75}};
  for (const auto& v : variants) {
    lms2xx_config c = Host::quick_config();
    c.units = LMS2XX_UNITS_MM;
    c.scan_angle_deg = v.angle;
    c.resolution_cdeg = v.res_cdeg;
    Host h(c);
    h.scene.walls = {{2.0, 90 * kDeg}};
    h.scene.sweep_coded = true;
    h.power_up();
    h.transact({0x20, 0x48}, 9600);
    std::vector<Item> scans;
    // Poll again as soon as each answer is complete, for 2 s.
    const int64_t t_end = h.now + 2 * kS;
    h.take();
    while (h.now < t_end) {
      h.send({0x30, 0x01}, 500000);
      std::vector<Item> got;
      while (got.empty() || got.back().code() != 0xB0) {
        h.run_for(kMs / 4);  // the host looks every 0.25 ms
        for (const Item& it : h.take()) got.push_back(it);
        ASSERT_LT(got.size(), 3u);
      }
      ASSERT_EQ(got.size(), 2u);
      EXPECT_EQ(got[0].code(), LMS2XX_ACK);
      scans.push_back(got[1]);
    }
    // The first polls may find a complete scan not yet sent and get it at once; from the third
    // on, each waits for its scan's last sweep to end, so answers start a scan period apart,
    // exact to the 1 ns rounding of the sweep grid.
    ASSERT_GE(scans.size(), 10u);
    const double period_ns = 1e9 / v.scans_per_s;
    for (size_t i = 3; i < scans.size(); ++i)
      EXPECT_NEAR(double(scans[i].start_ns() - scans[i - 1].start_ns()), period_ns, 1.0) << v.res_cdeg << " " << i;
    const double span_s = double(scans.back().start_ns() - scans[2].start_ns()) / 1e9;
    EXPECT_NEAR(double(scans.size() - 3) / span_s, v.scans_per_s, v.scans_per_s * 1e-6) << v.res_cdeg;
    // The value straight ahead tells the sweep it came from: consecutive answers are whole scans
    // one after the other (sweeps_per_scan apart), none repeated, none skipped.
    const size_t ahead = (v.angle == 180 ? 90u : 50u) * 100u / v.res_cdeg;
    const int64_t per_scan = 100 / v.res_cdeg;
    for (size_t i = 1; i < scans.size(); ++i)
      EXPECT_EQ((values_of(scans[i])[ahead] - values_of(scans[i - 1])[ahead] + 1000) % 1000, per_scan) << i;
  }
}

// A stop request (0x20 0x25) sent while a scan telegram is on the line waits for it: the LMS
// never breaks a telegram, so the ACK starts at the telegram's last stop bit and the 0xA0 answer
// follows; then no more scans. At 9600 a 180 deg / 0.5 deg telegram (732 bytes) lasts 762.5 ms,
// so the wait reaches that minus the request's own length (docs/lms2xx.md lists every rate).
TEST(Lms2xxProtocol, AStopRequestWaitsBehindTheTelegramOnTheLine) {
  Host h(Host::quick_config());
  h.scene.walls = {{2.0, 90 * kDeg}};
  h.power_up();
  h.take();
  h.send({0x20, 0x24}, 9600);
  h.run_for(50 * kMs);
  std::vector<Item> items = h.take();
  ASSERT_EQ(items.size(), 2u);  // ACK and A0; the first scan is on the line now
  // Send the stop 100 ms into a telegram that started after the A0.
  h.run_for(100 * kMs);
  const int64_t request_end = h.send({0x20, 0x25}, 9600);
  h.run_for(2 * kS);
  items = h.take();
  ASSERT_EQ(items.size(), 3u);  // the scan under way, ACK, A0 - and nothing after
  EXPECT_EQ(items[0].code(), 0xB0);
  EXPECT_EQ(items[0].bytes.size(), 732u);
  EXPECT_LT(items[0].start_ns(), request_end);
  EXPECT_EQ(items[1].code(), LMS2XX_ACK);
  EXPECT_EQ(items[1].start_ns(), items[0].last_end_ns);  // right behind it, not 1 ms after the request
  EXPECT_EQ(items[2].bytes, kModeChangeOk);
  const double telegram_ms = 732 * 10 / 9.6;  // 762.5 ms
  EXPECT_NEAR(double(items[0].last_end_ns - items[0].start_ns()) / 1e6, telegram_ms, 1e-3);
  // The wait: what was left of the telegram when the request had arrived.
  EXPECT_GT(items[1].start_ns() - request_end, 500 * kMs);
  EXPECT_LT(items[1].start_ns() - request_end, static_cast<int64_t>(telegram_ms * 1e6));
}

// sicktoolbox's ResetSick sends 0x10, waits for 0x91, switches its terminal to 9600 and waits
// for the 0x90 power-on message: the reply to a reset breaks the "request + 0x80" rule.
TEST(Lms2xxProtocol, ResetRebootsAtThePowerUpRate) {
  Host h(Host::quick_config());
  h.power_up();
  h.transact({0x20, 0x40}, 9600);
  h.transact({0x20, 0x24}, 38400);
  h.run_for(100 * kMs);
  h.take();
  h.send({0x10}, 38400);
  h.run_for(h.dev.config.power_up_ns + 2 * kS);  // the stream's telegram in flight ends first
  std::vector<uint8_t> codes;
  std::vector<uint32_t> bauds;
  for (const Item& it : h.take()) {
    codes.push_back(it.code());
    bauds.push_back(it.baud);
  }
  // What was on the line ends, then ACK, 0x91, and after rebooting the power-on message at 9600
  // with no stream any more (back to data on request).
  auto ack = std::find(codes.begin(), codes.end(), LMS2XX_ACK);
  ASSERT_NE(ack, codes.end());
  const size_t i = static_cast<size_t>(ack - codes.begin());
  ASSERT_EQ(codes.size(), i + 3);
  EXPECT_EQ(codes[i + 1], 0x91);
  EXPECT_EQ(bauds[i + 1], 38400u);
  EXPECT_EQ(codes[i + 2], LMS2XX_REPLY_POWER_ON);
  EXPECT_EQ(bauds[i + 2], 9600u);
  EXPECT_EQ(lms2xx_baud(&h.dev), 9600u);
}

// Scan contents against geometry, noise off: each value is the range rounded to the unit, and
// where nothing is within the mode's range, the "measured value > maximum" code 8 below the
// top of the value field (8183 = 0x1FF7 for 13 bits, 16375 for 14).
TEST(Lms2xxScan, ValuesFollowTheGeometryInEveryUnitAndRange) {
  struct Case {
    uint8_t units, mode;
    std::vector<Wall> walls;
    double unit_m;
    uint16_t over;
  };
  const Case cases[] = {
      // A wall 2 m ahead, mm, 8 m mode: r = 2 / sin(theta), past 8.182 m near the ends.
      {LMS2XX_UNITS_MM, LMS2XX_MEAS_8_80M_FA_FB_DAZZLE, {{2.0, 90 * kDeg}}, 0.001, 8183},
      // The same in cm (80 m mode): all but the grazing rays are in range.
      {LMS2XX_UNITS_CM, LMS2XX_MEAS_8_80M_FA_FB_DAZZLE, {{2.0, 90 * kDeg}}, 0.01, 8183},
      // A box corner: walls 1.5 m to the right and 2.5 m ahead.
      {LMS2XX_UNITS_MM, LMS2XX_MEAS_8_80M_REFLECTOR, {{1.5, 0.0}, {2.5, 90 * kDeg}}, 0.001, 8183},
      // 16 m mode (14-bit values): a wall 12 m ahead is in range, beyond 16.374 m is not.
      {LMS2XX_UNITS_MM, LMS2XX_MEAS_16M_FA_FB, {{12.0, 90 * kDeg}}, 0.001, 16375},
      // 32 m mode (15-bit values), a slanted wall.
      {LMS2XX_UNITS_MM, LMS2XX_MEAS_32M_FA, {{20.0, 60 * kDeg}}, 0.001, 32759},
      // The 8 m mode cannot see a wall 12 m away at all.
      {LMS2XX_UNITS_MM, LMS2XX_MEAS_8_80M_FA_FB_DAZZLE, {{12.0, 90 * kDeg}}, 0.001, 8183},
  };
  for (const Case& k : cases) {
    lms2xx_config c = Host::quick_config();
    c.units = k.units;
    c.measuring_mode = k.mode;
    Host h(c);
    h.scene.walls = k.walls;
    h.power_up();
    h.run_for(100 * kMs);
    const Item r = h.transact({0x30, 0x01}, 9600, 2 * kS);
    const auto p = r.payload();
    EXPECT_EQ(word_at(p, 1) >> LMS2XX_UNIT_SHIFT, k.units);
    const auto v = values_of(r);
    ASSERT_EQ(v.size(), 361u);
    int in_range = 0;
    for (size_t i = 0; i < v.size(); ++i) {
      const double range = h.scene.range(0.5 * kDeg * static_cast<double>(i));
      // In range: below the error codes and within the LMS's 80 m.
      const long code = std::lround(range / k.unit_m);
      const bool ok = range <= 80.0 && code < k.over;
      in_range += ok;
      EXPECT_EQ(v[i], ok ? code : k.over) << "value " << i << " mode " << int(k.mode);
    }
    // Every case has both kinds, but the last, which sees nothing (12 m is past 8.182 m).
    EXPECT_EQ(in_range > 0, &k != &cases[5]) << int(k.mode);
    EXPECT_LT(in_range, 361);
  }
}

// 0.25 degree resolution interlaces four sweeps offset by 0, 0.25, 0.5 and 0.75 degrees. In
// partial-scan mode (0x2A) each sweep is its own telegram with its offset in bits 11-12 and
// bit 13 set; in stream mode (0x24) the four are merged into 401 values.
TEST(Lms2xxScan, QuarterDegreeScansAreInterlaced) {
  lms2xx_config c = Host::quick_config();
  c.units = LMS2XX_UNITS_MM;
  c.scan_angle_deg = 100;
  c.resolution_cdeg = 25;
  Host h(c);
  h.scene.walls = {{1.0, 90 * kDeg}};  // r differs at every quarter degree, 1 to 1.56 m
  h.power_up();
  h.transact({0x20, 0x48}, 9600);
  h.transact({0x20, 0x2A}, 500000);
  auto scans = h.scans_over(200 * kMs);
  ASSERT_GE(scans.size(), 8u);
  // At 500 kBd a 101-value telegram (210 bytes, 4.2 ms) fits in a sweep: every sweep is sent.
  int prev = -1;
  for (const Item& s : scans) {
    const uint16_t word = word_at(s.payload(), 1);
    const int index = (word >> LMS2XX_PARTIAL_INDEX_SHIFT) & 3;
    EXPECT_TRUE(word & LMS2XX_PARTIAL_FLAG);
    if (prev >= 0) {
      EXPECT_EQ(index, (prev + 1) % 4);
    }
    prev = index;
    const auto v = values_of(s);
    ASSERT_EQ(v.size(), index == 0 ? 101u : 100u);
    for (size_t m = 0; m < v.size(); ++m) {
      const double theta = (40.0 + 0.25 * index + static_cast<double>(m)) * kDeg;
      EXPECT_EQ(v[m], std::lround(h.scene.range(theta) * 1000.0)) << index << " " << m;
    }
  }
  // Stream mode: 401 values, no partial flag, from four sweeps 13.33 ms apart.
  h.transact({0x20, 0x24}, 500000);
  h.scene.calls.clear();
  scans = h.scans_over(200 * kMs);
  ASSERT_GE(scans.size(), 2u);
  const uint16_t word = word_at(scans[0].payload(), 1);
  EXPECT_EQ(word & ~(3u << LMS2XX_UNIT_SHIFT), 401u);
  const auto v = values_of(scans[0]);
  for (size_t i = 0; i < v.size(); ++i)
    EXPECT_EQ(v[i], std::lround(h.scene.range((40.0 + 0.25 * static_cast<double>(i)) * kDeg) * 1000.0)) << i;
  ASSERT_EQ(h.scene.calls.size(), 4 * scans.size());
  for (size_t j = 0; j < 4; ++j) {
    EXPECT_NEAR(h.scene.calls[j].first_rad, (40.0 + 0.25 * static_cast<double>(j)) * kDeg, 1e-12);
    EXPECT_NEAR(h.scene.calls[j].step_rad, 1.0 * kDeg, 1e-12);
    EXPECT_EQ(h.scene.calls[j].count, j == 0 ? 101u : 100u);
    if (j) {
      EXPECT_NEAR(double(h.scene.calls[j].time_ns - h.scene.calls[j - 1].time_ns), double(kSweepNs), 1.0);
    }
  }
  // A full scan every fourth sweep: 53.3 ms apart (18.75 Hz).
  EXPECT_NEAR(double(scans[1].start_ns() - scans[0].start_ns()), 4.0 * 40e6 / 3.0, 1.0);
}

// The ROS sicklms node at 180 degrees reads partial scans (sicktoolbox GetSickPartialScan, mode
// 0x2A) and shifts each by 0.25 degree times its index: at 0.5 degree the sweeps alternate
// between index 0 (181 values from 0 degrees) and index 2 (180 values from 0.5 degrees).
TEST(Lms2xxScan, HalfDegreePartialScansAlternateOffsets) {
  Host h(Host::quick_config());
  h.scene.walls = {{1.0, 90 * kDeg}, {0.8, 0.0}, {0.8, 180 * kDeg}};
  h.power_up();
  h.transact({0x20, 0x48}, 9600);
  h.transact({0x20, 0x2A}, 500000);
  const auto scans = h.scans_over(100 * kMs);
  ASSERT_GE(scans.size(), 6u);
  int prev = -1;
  for (const Item& s : scans) {
    const uint16_t word = word_at(s.payload(), 1);
    const int index = (word >> LMS2XX_PARTIAL_INDEX_SHIFT) & 3;
    ASSERT_TRUE(index == 0 || index == 2);
    EXPECT_NE(index, prev);
    prev = index;
    const auto v = values_of(s);
    ASSERT_EQ(v.size(), index == 0 ? 181u : 180u);
    for (size_t m = 0; m < v.size(); ++m)
      EXPECT_EQ(v[m], std::lround(h.scene.range((0.25 * index + static_cast<double>(m)) * kDeg) * 100.0)) << m;
  }
}

// The line is the bottleneck: a 361-value scan is a 732-byte telegram, 7320 bit times. At
// 9600/19200/38400 baud the telegrams follow back to back, each the newest complete scan; at
// 500 kBd (14.6 ms a telegram) the 0.5 degree scan rate limits: 37.5 Hz, two 75 Hz sweeps.
TEST(Lms2xxScan, DeliveredRateIsSetByTheLine) {
  const struct {
    uint8_t code;
    uint32_t baud;
    double scans_per_s;
  } rates[] = {
      {0x42, 9600, 9600.0 / 7320.0},    // 1.31 scans/s
      {0x41, 19200, 19200.0 / 7320.0},  // 2.62
      {0x40, 38400, 38400.0 / 7320.0},  // 5.25: "about 5 scans a second"
      {0x48, 500000, 37.5},
  };
  for (const auto& rate : rates) {
    lms2xx_config c = Host::quick_config();
    c.units = LMS2XX_UNITS_MM;
    Host h(c);
    h.scene.walls = {{2.0, 90 * kDeg}};
    h.scene.sweep_coded = true;
    h.power_up();
    h.transact({0x20, rate.code}, 9600);
    h.transact({0x20, 0x24}, rate.baud);
    h.run_for(kS);
    h.take();
    h.scene.calls.clear();
    const uint64_t built_before = h.dev.scans_sent;
    const auto scans = h.scans_over(8 * kS);
    ASSERT_GE(scans.size(), 8u) << rate.baud;
    for (const Item& s : scans) ASSERT_EQ(s.bytes.size(), 732u);
    const double span_s = double(scans.back().start_ns() - scans.front().start_ns()) / 1e9;
    const double measured = double(scans.size() - 1) / span_s;
    // Telegram starts are exact to the ns (each byte frame is rounded to 1 ns).
    EXPECT_NEAR(measured, rate.scans_per_s, rate.scans_per_s * 1e-5) << rate.baud;
    // Only scans that went out were cast, two sweeps each: the window holds the telegrams built
    // in it, give or take the one in flight at either end.
    const uint64_t built = h.dev.scans_sent - built_before;
    EXPECT_EQ(h.scene.calls.size(), 2 * built) << rate.baud;
    EXPECT_LE(built, scans.size() + 1);
    EXPECT_GE(built + 1, scans.size());
    // Each telegram is the newest complete scan: the first of its two sweeps (read back from the
    // value straight ahead, index 180) ended with the scan less than a scan period (2 sweeps)
    // before the telegram started.
    for (const Item& s : scans) {
      const int64_t sweep_mod = values_of(s)[180] - 2000;
      // Interlaced: the odd values (here 90.5 degrees, 2.000076 m) come from the next sweep.
      EXPECT_EQ(values_of(s)[181] - 2000, (sweep_mod + 1) % 1000) << rate.baud;
      const int64_t start_sweep = Scene::sweep_of(s.start_ns());
      int64_t first = start_sweep - (start_sweep - sweep_mod) % 1000;
      while (first > start_sweep) first -= 1000;
      const int64_t scan_end = (first + 2) * 40000000 / 3;
      EXPECT_GE(s.start_ns() - scan_end, 0) << rate.baud;
      EXPECT_LT(s.start_ns() - scan_end, 2 * kSweepNs + 1) << rate.baud;
    }
  }
}

// Datasheet noise (technical description: statistical error 1 sigma = 5 mm, mm mode) and the
// counter-based draws: same seed, same bytes; another seed, other bytes.
TEST(Lms2xxScan, NoiseHasTheDatasheetSpreadAndIsDeterministic) {
  auto collect = [](uint64_t seed) {
    lms2xx_config c;
    lms2xx_default_config(&c);
    c.power_up_ns = 100 * kMs;
    c.units = LMS2XX_UNITS_MM;
    c.seed = seed;
    Host h(c);
    h.scene.walls = {{4.0, 90 * kDeg}};
    h.power_up();
    h.transact({0x20, 0x48}, 9600);
    h.transact({0x20, 0x24}, 500000);
    return h.scans_over(5 * kS);
  };
  const auto a = collect(7);
  const auto b = collect(7);
  const auto other = collect(8);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i].bytes, b[i].bytes);
  ASSERT_FALSE(other.empty());
  EXPECT_NE(a[0].bytes, other[0].bytes);

  // Residuals over the beams within 20 degrees of straight ahead (r < 4.26 m).
  double sum = 0, sum2 = 0;
  size_t n = 0;
  for (const Item& s : a) {
    const auto v = values_of(s);
    for (size_t i = 140; i <= 220; ++i) {
      const double truth_mm = 4000.0 / std::sin(0.5 * kDeg * static_cast<double>(i));
      const double e = v[i] - truth_mm;
      sum += e;
      sum2 += e * e;
      ++n;
    }
  }
  ASSERT_GT(n, 10000u);
  const double count = static_cast<double>(n);
  const double mean = sum / count;
  const double sd = std::sqrt(sum2 / count - mean * mean);
  // Rounding to 1 mm adds 1/12 mm^2 of variance: sqrt(25 + 1/12) = 5.008 mm. The sample sd of n
  // normal draws has relative sd 1/sqrt(2n); 4 of those, and 4 standard errors for the mean.
  EXPECT_NEAR(sd, 5.008, 4 * 5.008 / std::sqrt(2.0 * count));
  EXPECT_NEAR(mean, 0.0, 4 * 5.0 / std::sqrt(count));
}

}  // namespace
