// GPS: NMEA layouts and checksums of the u-blox NEO-6M and MediaTek MT3339 talkers, their UBX and
// PMTK configuration, timing at the baud rate, the receiver error statistics, the WGS-84 truth, and
// gpsd reading the stream.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "devices/gnss_error.h"
#include "devices/mtk3339.h"
#include "devices/nmea.h"
#include "devices/ublox_neo6m.h"
#include "sensors/gnss_truth.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::int64_t kSecond = 1000000000;
constexpr double kKnotsPerMps = 3600.0 / 1852.0;

// A rover driving east at 3 m/s and climbing at 0.1 m/s from the origin of a world at ETH
// Zurich's Hoenggerberg (a made-up origin; geoid separation 48 m, the EGM96 value thereabouts,
// held as the documented constant).
const sear::GeoPoint kOrigin{47.4085, 8.5077, 540.0};
constexpr double kGeoidSeparation = 48.0;
const sear::Enu kVelocity{3.0, 0.0, 0.1};

sear::GnssTruthFeed rover_feed() {
  return sear::GnssTruthFeed(sear::GnssTruth(kOrigin, kGeoidSeparation),
                             [](std::int64_t t, sear::Enu& p, sear::Enu& v) {
                               const double s = static_cast<double>(t) * 1e-9;
                               p = {kVelocity.east_m * s, kVelocity.north_m * s, kVelocity.up_m * s};
                               v = kVelocity;
                             });
}

// UTC at power-on for every test: 2026-11-24 07:00:00.
const std::int64_t kUtcStart = nmea_unix_s(2026, 11, 24, 7, 0, 0);

// A talker's config as every test powers it up: at kUtcStart, with the time to first fix it needs.
template <class Config>
Config talker_config(void (*defaults)(Config*), double ttff_s) {
  Config c;
  defaults(&c);
  c.utc_start_s = kUtcStart;
  c.error.ttff_s = ttff_s;
  return c;
}

template <class Dev, class Transmit>
std::vector<serial_byte> drain(Dev& d, Transmit transmit, std::int64_t from, std::int64_t to, std::int64_t step) {
  std::vector<serial_byte> out;
  serial_byte buf[512];
  for (std::int64_t t = from; t < to; t += step) {
    const std::int64_t until = std::min(t + step, to);
    for (;;) {
      const std::size_t n = transmit(&d, t, until, buf, 512);
      out.insert(out.end(), buf, buf + n);
      if (n < 512) break;
      t = until;  // what cap cut off comes with the same window's end
    }
  }
  return out;
}

std::string text_of(const std::vector<serial_byte>& bytes) {
  std::string s;
  for (const auto& b : bytes) s.push_back(static_cast<char>(b.value));
  return s;
}

std::vector<std::string> sentences(const std::string& s) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while ((at = s.find('$', at)) != std::string::npos) {
    const std::size_t end = s.find("\r\n", at);
    if (end == std::string::npos) break;
    out.push_back(s.substr(at, end + 2 - at));
    at = end + 2;
  }
  return out;
}

std::vector<std::string> split(const std::string& sentence) {
  const std::string body = sentence.substr(1, sentence.find('*') - 1);
  std::vector<std::string> f;
  std::stringstream ss(body);
  std::string item;
  while (std::getline(ss, item, ',')) f.push_back(item);
  if (!body.empty() && body.back() == ',') f.push_back("");
  return f;
}

bool checksum_ok(const std::string& s) {
  const char* body;
  std::size_t n;
  return nmea_parse_frame(s.data(), s.size(), &body, &n) == 1;
}

double nmea_angle(const std::string& value, const std::string& hemisphere) {
  const double v = std::stod(value);
  const double deg = std::floor(v / 100.0);
  const double result = deg + (v - 100.0 * deg) / 60.0;
  return hemisphere == "S" || hemisphere == "W" ? -result : result;
}

void send(ublox_neo6m& d, std::int64_t t, const std::vector<std::uint8_t>& bytes) {
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    serial_byte b{};
    b.baud = ublox_neo6m_baud(&d);
    b.end_ns = t + static_cast<std::int64_t>(i + 1) * serial_frame_ns(b.baud);
    b.value = bytes[i];
    ublox_neo6m_receive(&d, &b);
  }
}

void send(mtk3339& d, std::int64_t t, const std::string& text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    serial_byte b{};
    b.baud = mtk3339_baud(&d);
    b.end_ns = t + static_cast<std::int64_t>(i + 1) * serial_frame_ns(b.baud);
    b.value = static_cast<std::uint8_t>(text[i]);
    mtk3339_receive(&d, &b);
  }
}

bool contains(const std::string& hay, const std::vector<std::uint8_t>& needle) {
  return hay.find(std::string(needle.begin(), needle.end())) != std::string::npos;
}

std::vector<serial_byte> ublox_run(ublox_neo6m& d, std::int64_t from, std::int64_t to) {
  return drain(d, ublox_neo6m_transmit, from, to, 1000000);
}

}  // namespace

// Checksums and the power-up stream against sentences logged from real NEO-6M modules (the
// banner and the empty no-fix forms quoted in the issue) and the u-blox 6 Receiver Description's
// NMEA examples; lengths and field counts of every sentence of a fixed cycle.
TEST(GnssNmea, PowerUpBannerNoFixFormsAndFixedCycleLayout) {
  // u-blox 6 Receiver Description (GPS.G6-SW-10018), NMEA protocol chapter examples.
  for (const char* published : {"$GPRMC,083559.00,A,4717.11437,N,00833.91522,E,0.004,77.52,091202,,,A*57\r\n",
                                "$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B\r\n",
                                "$GPGSA,A,3,23,29,07,08,09,18,26,28,,,,,1.94,1.18,1.54*0D\r\n"}) {
    std::string s(published);
    const std::string body = s.substr(1, s.find('*') - 1);
    char out[NMEA_MAX_SENTENCE + 1];
    ASSERT_EQ(nmea_finish(out, sizeof out, body.c_str()), s.size());
    EXPECT_EQ(std::string(out), s);
  }

  auto feed = rover_feed();
  ublox_neo6m_config c = talker_config(ublox_neo6m_defaults, 5.0);
  ublox_neo6m d;
  ublox_neo6m_init(&d, &c, feed.source(), 0);
  const auto lines = sentences(text_of(ublox_run(d, 0, 15 * kSecond)));
  // Logged from a NEO-6M at power-up (firmware 7.03): banner, then the first no-fix cycle.
  const std::vector<std::string> expected = {
      "$GPTXT,01,01,02,u-blox ag - www.u-blox.com*50\r\n",
      "$GPTXT,01,01,02,HW  UBX-G60xx  00040007 FF7FFFFFp*53\r\n",
      "$GPTXT,01,01,02,ROM CORE 7.03 (45969) Mar 17 2011 16:18:34*59\r\n",
      "$GPTXT,01,01,02,ANTSUPERV=AC SD PDoS SR*20\r\n",
      "$GPTXT,01,01,02,ANTSTATUS=DONTKNOW*33\r\n",
      "$GPRMC,,V,,,,,,,,,,N*53\r\n",
      "$GPVTG,,,,,,,,,N*30\r\n",
      "$GPGGA,,,,,,0,00,99.99,,,,,,*48\r\n",
      "$GPGSA,A,1,,,,,,,,,,,,,99.99,99.99,99.99*30\r\n",
      "$GPGSV,1,1,00*79\r\n",
      "$GPGLL,,,,,,V,N*64\r\n"};
  ASSERT_GE(lines.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(lines[i], expected[i]) << i;

  // Fixed cycles: 12 satellites in view (GSV 3 parts), order RMC VTG GGA GSA GSV GLL.
  int cycles = 0;
  double last_time = -1.0;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const auto& s = lines[i];
    EXPECT_LE(s.size(), 82u) << s;  // NMEA 0183 5.3
    EXPECT_TRUE(checksum_ok(s)) << s;
    const auto f = split(s);
    const std::string id = f[0];
    // RMC: time, status, lat, N, lon, E, sog, cog, date, mv, E, mode; GSA: mode, fix, 12 PRNs, 3 DOPs.
    const std::size_t fields = id == "GPRMC" ? 13 : id == "GPVTG" ? 10 : id == "GPGGA" ? 15 : id == "GPGSA" ? 18
                             : id == "GPGLL" ? 8 : id == "GPTXT" ? 5 : 4 + 4 * ((f.size() - 4) / 4);
    EXPECT_EQ(f.size(), fields) << s;
    if (id == "GPRMC" && f[2] == "A") {
      ++cycles;
      const double t = std::stod(f[1].substr(0, 2)) * 3600 + std::stod(f[1].substr(2, 2)) * 60 + std::stod(f[1].substr(4));
      ASSERT_EQ(lines[i + 1].substr(0, 6), "$GPVTG");
      ASSERT_EQ(lines[i + 2].substr(0, 6), "$GPGGA");
      ASSERT_EQ(lines[i + 3].substr(0, 6), "$GPGSA");
      ASSERT_EQ(lines[i + 4].substr(0, 12), "$GPGSV,3,1,1");
      ASSERT_EQ(lines[i + 6].substr(0, 12), "$GPGSV,3,3,1");
      ASSERT_EQ(lines[i + 7].substr(0, 6), "$GPGLL");
      EXPECT_EQ(f[9], "241126");  // date ddmmyy
      // hhmmss.ss, one second per cycle from 07:00:00 UTC.
      if (last_time >= 0) {
        EXPECT_DOUBLE_EQ(t - last_time, 1.0);
      }
      last_time = t;
      EXPECT_EQ(f[3].size(), 10u);  // ddmm.mmmmm
      EXPECT_EQ(f[5].size(), 11u);  // dddmm.mmmmm
      // The position is the rover's within 4.5 sigma of the horizontal error (at t = whole seconds).
      const sear::GnssTruth truth(kOrigin, kGeoidSeparation);
      const double since = t - 7 * 3600;
      const sear::Enu got = truth.plane().to_enu({nmea_angle(f[3], f[4]), nmea_angle(f[5], f[6]), kOrigin.altitude_m});
      EXPECT_LT(std::hypot(got.east_m - kVelocity.east_m * since, got.north_m - kVelocity.north_m * since),
                4.5 * d.error.sigma_horizontal_m)
          << s;
      // Speed and course from the motion (3 m/s east): noise 0.1 m/s per axis, 5 sigma.
      EXPECT_NEAR(std::stod(f[7]) / kKnotsPerMps, 3.0, 0.5);
      EXPECT_NEAR(std::stod(f[8]), 90.0, std::atan(0.5 / 3.0) * 180 / kPi);
    }
  }
  // Fix from 5 s on; epochs every whole second from 07:00:01 to 07:00:14.
  EXPECT_EQ(cycles, 10);
}

// Bytes leave back to back at the baud rate, the first NMEA byte UBLOX_OUTPUT_DELAY_NS after the
// epoch; a cycle that does not fit drops whole sentences (the line never carries more than baud/10
// bytes a second) and never cuts one. The byte stream does not depend on how the caller slices time.
TEST(GnssNmea, TimingAtTheBaudRateAndOverflow) {
  auto feed = rover_feed();
  ublox_neo6m_config c = talker_config(ublox_neo6m_defaults, 0.0);
  ublox_neo6m a, b;
  ublox_neo6m_init(&a, &c, feed.source(), 0);
  ublox_neo6m_init(&b, &c, feed.source(), 0);
  const auto fine = ublox_run(a, 0, 5 * kSecond);
  const auto coarse = drain(b, ublox_neo6m_transmit, 0, 5 * kSecond, 7777777);
  ASSERT_EQ(fine.size(), coarse.size());
  for (std::size_t i = 0; i < fine.size(); ++i) ASSERT_EQ(fine[i].end_ns, coarse[i].end_ns);
  EXPECT_EQ(text_of(fine), text_of(coarse));

  const std::int64_t frame = serial_frame_ns(9600);
  EXPECT_EQ(frame, 1041667);  // 10 bits at 9600 baud
  // The cycle of the epoch at 07:00:01 starts 50 ms after it.
  auto first = std::find_if(fine.begin(), fine.end(), [](const serial_byte& x) { return x.end_ns > kSecond; });
  ASSERT_NE(first, fine.end());
  EXPECT_EQ(first->end_ns, kSecond + UBLOX_OUTPUT_DELAY_NS + frame);
  EXPECT_EQ(first->value, '$');
  for (auto it = first + 1; it != fine.end() && it->end_ns < 2 * kSecond; ++it)
    if (it->end_ns - (it - 1)->end_ns != frame) {
      ADD_FAILURE() << "gap inside the burst";  // one cycle (~600 bytes) fits a second at 9600
      break;
    }

  // A caller that skips a span [1.3 s, 1.5 s) gets nothing that started in it ("none starting
  // before now_ns"), and the bytes after it at their own times.
  ublox_neo6m skip;
  ublox_neo6m_init(&skip, &c, feed.source(), 0);
  auto part = drain(skip, ublox_neo6m_transmit, 0, 1300000000, 1000000);
  const auto rest = drain(skip, ublox_neo6m_transmit, 1500000000, 3 * kSecond, 1000000);
  ASSERT_FALSE(rest.empty());
  EXPECT_GE(rest.front().end_ns - frame, 1500000000);
  part.insert(part.end(), rest.begin(), rest.end());
  std::vector<serial_byte> expected;
  for (const auto& x : fine)
    if (x.end_ns < 3 * kSecond && (x.end_ns < 1300000000 || x.end_ns - frame >= 1500000000)) expected.push_back(x);
  ASSERT_EQ(part.size(), expected.size());
  EXPECT_EQ(text_of(part), text_of(expected));

  // 10 Hz at 9600 baud: about 6000 bytes a second asked of a 960 byte/s line.
  c.rate_hz = 10.0;
  ublox_neo6m fast;
  ublox_neo6m_init(&fast, &c, feed.source(), 0);
  const auto over = ublox_run(fast, 0, 10 * kSecond);
  for (std::size_t i = 1; i < over.size(); ++i) ASSERT_GE(over[i].end_ns - over[i - 1].end_ns, frame);
  const auto lines = sentences(text_of(over));
  for (const auto& s : lines) ASSERT_TRUE(checksum_ok(s)) << s;
  EXPECT_GT(fast.tx.dropped_bytes, 0u);
  // Over 9 s the line is busy all the time, at most 960 bytes a second.
  EXPECT_GT(over.size(), 8u * 960u);
  EXPECT_LE(over.size(), 10u * 960u);
  // At 115200 baud the same 10 Hz fits: RMC of every epoch 0.2 s ... 10.0 s, none dropped.
  c.baud = 115200;
  ublox_neo6m_init(&fast, &c, feed.source(), 0);
  const auto all = sentences(text_of(ublox_run(fast, 0, 10 * kSecond + 60000000)));
  EXPECT_EQ(std::count_if(all.begin(), all.end(), [](const std::string& s) { return s.rfind("$GPRMC", 0) == 0; }),
            99);
  EXPECT_EQ(fast.tx.dropped_bytes, 0u);
}

// UBX: the CFG-RATE vector and its ACK, CFG-MSG, CFG-PRT baud change, NAK for what a u-blox 6
// does not have, a bad checksum ignored; PUBX,40; PMTK ignored.
TEST(GnssUbx, ConfigurationAndAcknowledgements) {
  auto feed = rover_feed();
  ublox_neo6m_config c = talker_config(ublox_neo6m_defaults, 0.0);
  ublox_neo6m d;
  ublox_neo6m_init(&d, &c, feed.source(), 0);
  std::string out = text_of(ublox_run(d, 0, 1500000000));

  // CFG-RATE 200 ms, navRate 1, timeRef GPS: bytes and answer quoted in the issue.
  const std::vector<std::uint8_t> rate5 = {0xB5, 0x62, 0x06, 0x08, 0x06, 0x00, 0xC8, 0x00, 0x01, 0x00, 0x01, 0x00, 0xDE, 0x6A};
  std::uint8_t frame[16];
  const std::uint8_t payload[6] = {0xC8, 0x00, 0x01, 0x00, 0x01, 0x00};
  ASSERT_EQ(ubx_frame(0x06, 0x08, payload, 6, frame), rate5.size());
  EXPECT_TRUE(std::equal(rate5.begin(), rate5.end(), frame));  // our Fletcher checksum gives DE 6A
  send(d, 1500000000, rate5);
  out = text_of(ublox_run(d, 1500000000, 3 * kSecond));
  EXPECT_TRUE(contains(out, {0xB5, 0x62, 0x05, 0x01, 0x02, 0x00, 0x06, 0x08, 0x16, 0x3F}));
  // Epochs every 0.2 s from then on (at 9600 baud part of each cycle is dropped, whole sentences).
  int off_second = 0;
  for (const auto& s : sentences(out)) {
    ASSERT_TRUE(checksum_ok(s)) << s;
    const auto f = split(s);
    if (f[0] != "GPRMC" && f[0] != "GPGGA") continue;
    const int centiseconds = std::stoi(f[1].substr(4, 2)) * 100 + std::stoi(f[1].substr(7, 2));
    EXPECT_EQ(centiseconds % 20, 0) << s;
    if (centiseconds % 100 != 0) ++off_second;
  }
  EXPECT_GE(off_second, 4);

  // CFG-MSG: GSV (F0 03) off on UART1; CFG-RATE back to 1 Hz.
  std::uint8_t buf[32];
  const std::uint8_t gsv_off[3] = {0xF0, 0x03, 0x00};
  std::size_t n = ubx_frame(0x06, 0x01, gsv_off, 3, buf);
  send(d, 3 * kSecond, std::vector<std::uint8_t>(buf, buf + n));
  const std::uint8_t rate1[6] = {0xE8, 0x03, 0x01, 0x00, 0x01, 0x00};
  n = ubx_frame(0x06, 0x08, rate1, 6, buf);
  send(d, 3 * kSecond + 50000000, std::vector<std::uint8_t>(buf, buf + n));
  // CFG-MSG for UBX NAV-PVT (01 07): a message u-blox 7 brought, so a u-blox 6 refuses it (ACK-NAK,
  // class 05 id 00).
  const std::uint8_t pvt[3] = {0x01, 0x07, 0x01};
  n = ubx_frame(0x06, 0x01, pvt, 3, buf);
  send(d, 3 * kSecond + 100000000, std::vector<std::uint8_t>(buf, buf + n));
  // A corrupted checksum is ignored (no answer at all).
  n = ubx_frame(0x06, 0x08, rate1, 6, buf);
  buf[n - 1] ^= 0x55;
  send(d, 3 * kSecond + 150000000, std::vector<std::uint8_t>(buf, buf + n));
  // A MediaTek command means nothing to a u-blox.
  const std::string pmtk = "$PMTK220,100*2F\r\n";
  send(d, 3 * kSecond + 200000000, std::vector<std::uint8_t>(pmtk.begin(), pmtk.end()));
  // PUBX,40: GLL off on UART1.
  const std::string pubx = "$PUBX,40,GLL,0,0,0,0*5C\r\n";
  send(d, 3 * kSecond + 300000000, std::vector<std::uint8_t>(pubx.begin(), pubx.end()));
  EXPECT_EQ(d.acks, 3u);
  EXPECT_EQ(d.naks, 1u);
  out = text_of(ublox_run(d, 3 * kSecond, 8 * kSecond));
  std::uint8_t ack[10];
  const std::uint8_t msg[2] = {0x06, 0x01};
  ubx_frame(0x05, 0x00, msg, 2, ack);
  EXPECT_TRUE(contains(out, std::vector<std::uint8_t>(ack, ack + 10)));
  // From the first epoch after the commands on: no GSV or GLL, 1 Hz (the PMTK220 did nothing).
  const std::size_t from = out.find("$GPRMC,070004.00,");
  ASSERT_NE(from, std::string::npos);
  const auto lines = sentences(out.substr(from));
  int gga = 0;
  for (const auto& s : lines) {
    EXPECT_NE(s.substr(0, 6), "$GPGSV");
    EXPECT_NE(s.substr(0, 6), "$GPGLL");
    if (s.rfind("$GPGGA", 0) == 0) ++gga;
  }
  EXPECT_EQ(gga, 4);  // 07:00:04 ... 07

  // CFG-PRT UART1 to 38400 8N1, NMEA+UBX in and out: ACK at 9600, then the line runs at 38400.
  std::uint8_t prt[20] = {1, 0, 0, 0, 0xD0, 0x08, 0, 0, 0x00, 0x96, 0x00, 0x00, 3, 0, 3, 0, 0, 0, 0, 0};
  n = ubx_frame(0x06, 0x00, prt, 20, buf);
  send(d, 8 * kSecond + 500000000, std::vector<std::uint8_t>(buf, buf + n));
  const auto after = ublox_run(d, 8 * kSecond, 11 * kSecond);
  EXPECT_EQ(ublox_neo6m_baud(&d), 38400u);
  ASSERT_GE(after.size(), 10u);
  const auto ack_at = std::find_if(after.begin(), after.end(), [](const serial_byte& x) { return x.value == 0xB5; });
  ASSERT_NE(ack_at, after.end());
  EXPECT_EQ(ack_at->baud, 9600u);
  EXPECT_EQ(after.back().baud, 38400u);
  EXPECT_NE(text_of(after).find("$GPGGA,070010.00,"), std::string::npos);
}

// MediaTek: boot messages, RTC time before the fix, PMTK220/314 with their PMTK001 answers, UBX
// ignored, the MTK number formats.
TEST(GnssMtk, PmtkCommandsAndFlavour) {
  auto feed = rover_feed();
  mtk3339_config c = talker_config(mtk3339_defaults, 3.0);
  mtk3339 d;
  mtk3339_init(&d, &c, feed.source(), 0);
  auto run = [&d](std::int64_t a, std::int64_t b) { return text_of(drain(d, mtk3339_transmit, a, b, 1000000)); };
  std::string out = run(0, 2500000000);
  auto lines = sentences(out);
  ASSERT_GE(lines.size(), 3u);
  EXPECT_EQ(lines[0], "$PMTK011,MTKGPS*08\r\n");
  EXPECT_EQ(lines[1], "$PMTK010,001*2E\r\n");
  // Before the fix: RTC time from 1980-01-06 (one second after power-on), no position.
  EXPECT_EQ(lines[2].substr(0, 27), "$GPGGA,000001.000,,,,,0,0,,");
  EXPECT_NE(out.find("$GPRMC,000001.000,V,,,,,0.00,0.00,060180,,,N*"), std::string::npos);

  const std::vector<std::uint8_t> ubx_rate = {0xB5, 0x62, 0x06, 0x08, 0x06, 0x00, 0xC8, 0x00, 0x01, 0x00, 0x01, 0x00, 0xDE, 0x6A};
  send(d, 2500000000, std::string(ubx_rate.begin(), ubx_rate.end()));
  send(d, 2600000000, "$PMTK220,200*2C\r\n");
  send(d, 2700000000, "$PMTK314,0,1,0,1,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0*28\r\n");  // RMC and GGA only
  send(d, 2800000000, "$PMTK999,1*00\r\n");  // bad checksum: ignored
  send(d, 2850000000, "$PMTK999*3B\r\n");    // unknown: "unsupported"
  out = run(2500000000, 6 * kSecond);
  EXPECT_NE(out.find("$PMTK001,220,3*30\r\n"), std::string::npos);
  EXPECT_NE(out.find("$PMTK001,314,3*36\r\n"), std::string::npos);
  EXPECT_NE(out.find("$PMTK001,999,1*"), std::string::npos);
  EXPECT_EQ(out.find("\xB5\x62"), std::string::npos);
  EXPECT_EQ(d.acks, 3u);
  lines = sentences(out);
  int gga = 0, rmc = 0;
  for (const auto& s : lines) {
    EXPECT_TRUE(checksum_ok(s)) << s;
    EXPECT_LE(s.size(), 82u);
    const auto f = split(s);
    // Fixed epochs (from 3 s) before 07:00:05.5.
    if (f[0] == "GPGGA" && f[6] == "1" && f[1] < "070005.500") ++gga;
    if (f[0] == "GPRMC" && f[2] == "A" && f[1] < "070005.500") ++rmc;
    EXPECT_TRUE(f[0] == "GPGGA" || f[0] == "GPRMC" || f[0].rfind("PMTK", 0) == 0) << s;
    if (f[0] == "GPGGA" && f[6] == "1") {
      EXPECT_EQ(f[1].size(), 10u);  // hhmmss.sss
      EXPECT_EQ(f[2].size(), 9u);   // ddmm.mmmm
      EXPECT_EQ(f[4].size(), 10u);  // dddmm.mmmm
      EXPECT_EQ(f[7], std::to_string(d.error.used_count));  // not zero-padded
    }
  }
  // 5 Hz: 07:00:03.0, 03.2, ... 05.4.
  EXPECT_EQ(gga, 13);
  EXPECT_EQ(rmc, 13);

  // PMTK251: no acknowledgement; the port switches and the next sentences leave at 38400.
  send(d, 6 * kSecond + 100000000, "$PMTK251,38400*27\r\n");
  EXPECT_EQ(mtk3339_baud(&d), 38400u);
  const auto fast = drain(d, mtk3339_transmit, 6 * kSecond, 7 * kSecond, 1000000);
  ASSERT_FALSE(fast.empty());
  EXPECT_EQ(fast.back().baud, 38400u);
  EXPECT_EQ(d.acks, 3u);
}

// Error model: CEP of the horizontal error within 10 % of the configured value (sample median
// of the radius; with 4000 near-independent draws its relative standard error is
// 0.72/sqrt(4000) = 1.1 %, so 10 % fails only if the model is wrong), vertical and velocity sigmas,
// the Gauss-Markov correlation at one time constant (exp(-1)), the same tick giving the same error
// whatever was asked before, and the sky's DOPs against an independent computation.
TEST(GnssErrorModel, StatisticsCorrelationAndDop) {
  gnss_error_config c;
  gnss_error_defaults(&c);
  c.correlation_s = 2.0;  // stationary statistics do not depend on tau; short keeps the test fast
  c.seed = 42;
  gnss_error m;
  gnss_error_init(&m, &c);
  const int n = 4000;
  const std::int64_t spacing = 10 * kSecond;  // 5 tau: correlation exp(-5) = 0.7 %
  std::vector<double> radius, up, ve;
  double lag_xy = 0, lag_xx = 0, lag_yy = 0;
  for (int i = 0; i < n; ++i) {
    gnss_error_sample s, later;
    gnss_error_at(&m, i * spacing, &s);
    radius.push_back(std::hypot(s.east_m, s.north_m));
    up.push_back(s.up_m);
    ve.push_back(s.east_mps);
    gnss_error_at(&m, i * spacing + 2 * kSecond, &later);  // one tau later
    lag_xy += s.east_m * later.east_m;
    lag_xx += s.east_m * s.east_m;
    lag_yy += later.east_m * later.east_m;
  }
  std::vector<double> sorted = radius;
  std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
  EXPECT_NEAR(sorted[n / 2], GNSS_DEFAULT_CEP_M, 0.10 * GNSS_DEFAULT_CEP_M);
  auto rms = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x * x;
    return std::sqrt(s / static_cast<double>(v.size()));
  };
  // Sample sd: relative standard error 1/sqrt(2n) = 1.1 %; 5 % bounds.
  EXPECT_NEAR(rms(up), m.sigma_vertical_m, 0.05 * m.sigma_vertical_m);
  EXPECT_GT(m.sigma_vertical_m, m.sigma_horizontal_m);  // vertical worse, as VDOP > HDOP
  EXPECT_NEAR(rms(ve), GNSS_DEFAULT_VELOCITY_SD_MPS, 0.05 * GNSS_DEFAULT_VELOCITY_SD_MPS);
  // Correlation coefficient's standard error (1 - r^2)/sqrt(n) = 0.014; 4 sigma.
  EXPECT_NEAR(lag_xy / std::sqrt(lag_xx * lag_yy), std::exp(-1.0), 0.06);

  // A tick's error is a function of the tick: asked cold, after others, and in reverse order.
  gnss_error fresh;
  gnss_error_init(&fresh, &c);
  gnss_error_sample x, y;
  gnss_error_at(&fresh, 123456789012, &x);
  gnss_error_at(&m, 123456789012, &y);
  EXPECT_EQ(x.east_m, y.east_m);
  EXPECT_EQ(x.up_m, y.up_m);
  EXPECT_EQ(x.north_mps, y.north_mps);

  // DOPs of the used satellites from the fixed sky, computed independently here: least squares
  // geometry with the receiver clock, Q = (G^T G)^-1 by Cramer-free Gaussian elimination on
  // normal equations solved for each unit vector.
  const gnss_sky_satellite* sky = gnss_error_sky();
  double g[4][4] = {};
  for (int i = 0; i < m.used_count; ++i) {
    const double el = sky[i].elevation_deg * kPi / 180, az = sky[i].azimuth_deg * kPi / 180;
    const double row[4] = {std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el), 1.0};
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k) g[r][k] += row[r] * row[k];
  }
  double q[4];  // diagonal of the inverse, column by column
  for (int col = 0; col < 4; ++col) {
    double a[4][5];
    for (int r = 0; r < 4; ++r) {
      for (int k = 0; k < 4; ++k) a[r][k] = g[r][k];
      a[r][4] = r == col ? 1.0 : 0.0;
    }
    for (int p = 0; p < 4; ++p)
      for (int r = p + 1; r < 4; ++r) {
        const double f = a[r][p] / a[p][p];
        for (int k = p; k < 5; ++k) a[r][k] -= f * a[p][k];
      }
    double x4[4];
    for (int r = 3; r >= 0; --r) {
      double s = a[r][4];
      for (int k = r + 1; k < 4; ++k) s -= a[r][k] * x4[k];
      x4[r] = s / a[r][r];
    }
    q[col] = x4[col];
  }
  EXPECT_NEAR(m.hdop, std::sqrt(q[0] + q[1]), 1e-9);
  EXPECT_NEAR(m.vdop, std::sqrt(q[2]), 1e-9);
  EXPECT_NEAR(m.pdop, std::sqrt(q[0] + q[1] + q[2]), 1e-9);
  // HDOP agrees with the error: DRMS = HDOP * UERE, with a UERE typical of an unaided L1 C/A
  // receiver (a few metres).
  EXPECT_NEAR(m.hdop * m.uere_m, std::sqrt(2.0) * m.sigma_horizontal_m, 1e-9);
  EXPECT_GT(m.uere_m, 2.0);
  EXPECT_LT(m.uere_m, 4.5);
  // A poorer configured accuracy shows as fewer satellites and a larger HDOP, not a worse UERE.
  gnss_error poor;
  c.cep_m = 8.0;
  gnss_error_init(&poor, &c);
  EXPECT_LT(poor.used_count, m.used_count);
  EXPECT_GT(poor.hdop, m.hdop);
  EXPECT_GE(poor.used_count, GNSS_MIN_USED);

  // Time to first fix.
  EXPECT_FALSE(gnss_error_has_fix(&m, 27 * kSecond - 1));
  EXPECT_TRUE(gnss_error_has_fix(&m, 27 * kSecond));
  // Satellites acquired one by one before the fix: none in the first second (as logged).
  EXPECT_EQ(gnss_error_tracked(&m, kSecond), 0);
  EXPECT_EQ(gnss_error_tracked(&m, 3 * kSecond), 3);
}

// Geodesy against GeographicLib 2.1.2's CartConvert (an independent, exact implementation):
// `echo 33.3 44.4 6000 | CartConvert -l 33 44 20` gives 37288.973197 33374.294947 5783.646616, and
// `CartConvert -r -l 47.4085 8.5077 540` turns local points within 10 km into the geodetic points
// below. Then points within 10 km of four origins checked against the closed-form geodetic -> ECEF.
TEST(GnssTruth, WgsGeodesyAndVelocityFrame) {
  const sear::LocalTangentPlane cart({33.0, 44.0, 20.0});
  const sear::Enu e = cart.to_enu({33.3, 44.4, 6000.0});
  EXPECT_NEAR(e.east_m, 37288.973197, 1e-5);
  EXPECT_NEAR(e.north_m, 33374.294947, 1e-5);
  EXPECT_NEAR(e.up_m, 5783.646616, 1e-5);
  struct Reference {
    sear::GeoPoint origin;
    sear::Enu local;
    sear::GeoPoint geo;
  };
  const Reference refs[] = {
      {kOrigin, {7000, -7000, 25}, {47.34550619437498, 8.60032805214951, 572.679723463}},
      {kOrigin, {-9999, 300, -40}, {47.41112160069661, 8.37522178731862, 507.829925935}},
      {kOrigin, {0, 10000, 0}, {47.49843679382420, 8.50770000000000, 547.848488083}},
      {{-33.8568, 151.2153, 10.0}, {1000, 2000, 3}, {-33.83876849222717, 151.22610390117367, 13.393011991}},
  };
  for (const auto& r : refs) {
    // 1e-9 degree is 0.1 mm; the issue asks for 1 cm.
    const gnss_fix_truth t = sear::GnssTruth(r.origin, kGeoidSeparation).at(0, r.local, {0, 0, 0});
    EXPECT_NEAR(t.latitude_deg, r.geo.latitude_deg, 1e-9);
    EXPECT_NEAR(t.longitude_deg, r.geo.longitude_deg, 1e-9);
    EXPECT_NEAR(t.altitude_msl_m + t.geoid_separation_m, r.geo.altitude_m, 1e-4);
    EXPECT_DOUBLE_EQ(t.geoid_separation_m, kGeoidSeparation);
  }

  const double a = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f);
  auto ecef = [&](double lat, double lon, double h, double out[3]) {
    const double sl = std::sin(lat * kPi / 180), cl = std::cos(lat * kPi / 180);
    const double n = a / std::sqrt(1 - e2 * sl * sl);
    out[0] = (n + h) * cl * std::cos(lon * kPi / 180);
    out[1] = (n + h) * cl * std::sin(lon * kPi / 180);
    out[2] = (n * (1 - e2) + h) * sl;
  };
  for (const sear::GeoPoint origin : {kOrigin, sear::GeoPoint{-33.8568, 151.2153, 10.0},
                                      sear::GeoPoint{0.0, 179.99, 0.0}, sear::GeoPoint{78.2, 15.6, 300.0}}) {
    const sear::GnssTruth truth(origin, kGeoidSeparation);
    double o[3];
    ecef(origin.latitude_deg, origin.longitude_deg, origin.altitude_m, o);
    const double sl = std::sin(origin.latitude_deg * kPi / 180), cl = std::cos(origin.latitude_deg * kPi / 180);
    const double so = std::sin(origin.longitude_deg * kPi / 180), co = std::cos(origin.longitude_deg * kPi / 180);
    for (int i = 0; i < 64; ++i) {
      const double ang = i * 2.399963, r = 10000.0 * std::sqrt((i + 0.5) / 64.0);
      const sear::Enu p{r * std::sin(ang), r * std::cos(ang), 50.0 * std::sin(i * 0.7)};
      const gnss_fix_truth t = truth.at(0, p, {0, 0, 0});
      double got[3];
      ecef(t.latitude_deg, t.longitude_deg, t.altitude_msl_m + t.geoid_separation_m, got);
      // Exact: origin + R^T enu.
      const double want[3] = {o[0] - so * p.east_m - sl * co * p.north_m + cl * co * p.up_m,
                              o[1] + co * p.east_m - sl * so * p.north_m + cl * so * p.up_m,
                              o[2] + cl * p.north_m + sl * p.up_m};
      const double err = std::sqrt(std::pow(got[0] - want[0], 2) + std::pow(got[1] - want[1], 2) +
                                   std::pow(got[2] - want[2], 2));
      ASSERT_LT(err, 0.01) << "origin " << origin.latitude_deg << " point " << i;
    }
    // A horizontal world velocity 10 km east: same speed, but climbing by the Earth's curvature
    // (10 km / N = 1.57 mrad) in the local frame there, as the tangent plane rises off the Earth.
    const sear::Enu v = truth.local_velocity({10000.0, 0, 0}, {10.0, 0, 0});
    EXPECT_NEAR(std::hypot(std::hypot(v.east_m, v.north_m), v.up_m), 10.0, 1e-9);
    const double n = a / std::sqrt(1 - e2 * sl * sl);
    EXPECT_NEAR(v.up_m, 10.0 * std::sin(10000.0 / n), 1e-4);
  }
  // WGS-84 reference points: equator/prime meridian at a, the pole at b = 6356752.3142 m
  // (NIMA TR8350.2 table 3.3).
  const sear::LocalTangentPlane equator({0.0, 0.0, 0.0});
  EXPECT_NEAR(equator.to_geo({0, 0, 0}).latitude_deg, 0.0, 1e-12);
  const sear::GeoPoint pole = equator.to_geo({0.0, 6356752.3142, -6378137.0});
  EXPECT_NEAR(pole.latitude_deg, 90.0, 1e-9);
  EXPECT_NEAR(pole.altitude_m, 0.0, 1e-3);

  const gnss_fix_truth moving = sear::GnssTruth(kOrigin, kGeoidSeparation).at(0, {0, 0, 0}, {-1.0, -1.0, 0.0});
  EXPECT_NEAR(sear::course_over_ground_deg(moving), 225.0, 1e-9);
  EXPECT_NEAR(sear::speed_over_ground_mps(moving), std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(moving.altitude_msl_m, kOrigin.altitude_m - kGeoidSeparation, 1e-6);
}

// gpsd 3.22 reads the NEO-6M's stream (through gpsfake's pty) and reports 3D fixes whose
// position, altitude, speed and track match the truth within the configured error: 4.5 sigma of
// each (Rayleigh tail exp(-4.5^2/2) = 4e-5 for the horizontal radius).
TEST(GnssGpsd, GpsfakeReportsTheTruthWithinTheError) {
  if (std::system("command -v gpsfake >/dev/null 2>&1") != 0) GTEST_SKIP() << "gpsfake not installed";
  auto feed = rover_feed();
  ublox_neo6m_config c = talker_config(ublox_neo6m_defaults, 0.0);
  c.error.seed = 7;
  ublox_neo6m d;
  ublox_neo6m_init(&d, &c, feed.source(), 0);
  const std::string stream = text_of(ublox_run(d, 0, 8 * kSecond));
  const std::string dir = ::testing::TempDir();
  const std::string log = dir + "/gnss_neo6m_" + std::to_string(getpid()) + ".nmea";
  std::ofstream(log, std::ios::binary) << stream;
  const int port = 40000 + getpid() % 20000;
  const std::string cmd = "timeout 60 gpsfake -1 -p -q -c 0.01 -P " + std::to_string(port) + " " + log + " 2>/dev/null";
  FILE* p = popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string json;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p)) json += buf;
  pclose(p);
  std::remove(log.c_str());

  const sear::GnssTruth truth(kOrigin, kGeoidSeparation);
  const double sh = d.error.sigma_horizontal_m, sv = d.error.sigma_vertical_m;
  int checked = 0;
  std::istringstream lines(json);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("{\"class\":\"TPV\"", 0) != 0) continue;
    const auto tpv = nlohmann::json::parse(line);
    if (tpv.value("mode", 0) != 3 || !tpv.contains("lat") || !tpv.contains("altMSL") || !tpv.contains("track"))
      continue;
    // The epoch from gpsd's time: seconds after 07:00:00 on the start day.
    const std::string iso = tpv["time"];
    ASSERT_EQ(iso.substr(0, 11), "2026-11-24T");
    const double s = std::stod(iso.substr(11, 2)) * 3600 + std::stod(iso.substr(14, 2)) * 60 +
                     std::stod(iso.substr(17)) - 7 * 3600;
    const auto t_ns = static_cast<std::int64_t>(std::llround(s * 1e9));
    const gnss_fix_truth want =
        truth.at(t_ns, {kVelocity.east_m * s, kVelocity.north_m * s, kVelocity.up_m * s}, kVelocity);
    const sear::Enu got =
        truth.plane().to_enu({tpv["lat"].get<double>(), tpv["lon"].get<double>(), want.altitude_msl_m + kGeoidSeparation});
    const sear::Enu ref = truth.plane().to_enu({want.latitude_deg, want.longitude_deg, want.altitude_msl_m + kGeoidSeparation});
    EXPECT_LT(std::hypot(got.east_m - ref.east_m, got.north_m - ref.north_m), 4.5 * sh) << line;
    EXPECT_NEAR(tpv["altMSL"].get<double>(), want.altitude_msl_m, 4.5 * sv + 0.05) << line;  // + printed 0.1 m
    EXPECT_NEAR(tpv["speed"].get<double>(), 3.0, 4.5 * 0.1 + 0.001) << line;
    EXPECT_NEAR(tpv["track"].get<double>(), 90.0, std::atan(4.5 * 0.1 / 3.0) * 180 / kPi) << line;
    ++checked;
  }
  EXPECT_GE(checked, 5) << json;
  std::printf("gpsd: %d 3D TPV reports checked; %d satellites used, HDOP %.2f, UERE %.2f m, vertical sd %.2f m\n",
              checked, d.error.used_count, d.error.hdop, d.error.uere_m, d.error.sigma_vertical_m);
}
