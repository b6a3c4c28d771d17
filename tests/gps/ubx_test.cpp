// The NEO-6M's UBX side: every NAV message's layout field by field against the u-blox 6 protocol
// specification (GPS.G6-SW-10018) and against the NMEA sentences of the same epoch; the ACK or NAK
// of each CFG message, including what a u-blox 6 must refuse; polls; and the port's bandwidth
// shared by UBX and NMEA.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "devices/ublox_neo6m.h"
#include "sensors/gnss_truth.hpp"
#include "ubx_stream.hpp"

namespace {

using sear::test::fields_of;
using sear::test::i2;
using sear::test::i4;
using sear::test::Item;
using sear::test::u2;
using sear::test::u4;
using sear::test::ubx_bytes;
using sear::test::UbxFrame;

constexpr double kPi = 3.14159265358979323846;
constexpr std::int64_t kMs = 1000000;
constexpr std::int64_t kSecond = 1000 * kMs;

// A rover at ETH Zurich's Hoenggerberg driving east at 3 m/s and climbing at 0.1 m/s, geoid 48 m
// above the ellipsoid (as tests/gnss_test.cpp).
const sear::GeoPoint kOrigin{47.4085, 8.5077, 540.0};
constexpr double kGeoid = 48.0;

sear::GnssTruthFeed rover_feed() {
  return sear::GnssTruthFeed(sear::GnssTruth(kOrigin, kGeoid), [](std::int64_t t, sear::Enu& p, sear::Enu& v) {
    const double s = static_cast<double>(t) * 1e-9;
    p = {3.0 * s, 0.0, 0.1 * s};
    v = {3.0, 0.0, 0.1};
  });
}

// Power-on at 2026-11-24 07:00:00 UTC, a fix from the first epoch on.
ublox_neo6m_config config(std::uint32_t baud) {
  ublox_neo6m_config c;
  ublox_neo6m_defaults(&c);
  c.utc_start_s = nmea_unix_s(2026, 11, 24, 7, 0, 0);
  c.error.ttff_s = 0.0;
  c.error.seed = 3;
  c.baud = baud;
  return c;
}

// The host sends bytes back to back at the receiver's rate from t.
std::int64_t send(ublox_neo6m& d, std::int64_t t, const std::vector<std::uint8_t>& bytes) {
  for (std::uint8_t v : bytes) {
    serial_byte b{};
    b.baud = ublox_neo6m_baud(&d);
    b.end_ns = t += serial_frame_ns(b.baud);
    b.value = v;
    ublox_neo6m_receive(&d, &b);
  }
  return t;
}

// What the receiver sends in [from, to), in 1 ms windows as the lockstep asks.
std::vector<serial_byte> run(ublox_neo6m& d, std::int64_t from, std::int64_t to) {
  std::vector<serial_byte> out;
  serial_byte buf[512];
  for (std::int64_t t = from; t < to; t += kMs) {
    std::size_t n;
    do {
      n = ublox_neo6m_transmit(&d, t, std::min(t + kMs, to), buf, 512);
      out.insert(out.end(), buf, buf + n);
    } while (n == 512);
  }
  return out;
}

// The messages of a capture; a message still being sent at its end waits for the next capture.
struct Line {
  std::vector<serial_byte> held;
  std::vector<Item> take(const std::vector<serial_byte>& more) {
    held.insert(held.end(), more.begin(), more.end());
    std::vector<std::string> bad;
    std::size_t used = 0;
    auto out = sear::test::split_stream(held, bad, &used);
    for (const auto& b : bad) ADD_FAILURE() << "malformed output: " << b;
    held.erase(held.begin(), held.begin() + static_cast<std::ptrdiff_t>(used));
    return out;
  }
};
Line line;  // one receiver's output at a time: each test starts it anew

std::vector<Item> items(const std::vector<serial_byte>& bytes) { return line.take(bytes); }

// The NAV message ids of the u-blox 6 spec's NAV class, with their payload lengths there.
const std::map<std::uint8_t, std::size_t> kNavLength = {
    {0x01, 20} /* POSECEF */, {0x02, 28} /* POSLLH */, {0x03, 16} /* STATUS */, {0x04, 18} /* DOP */,
    {0x06, 52} /* SOL */,     {0x11, 20} /* VELECEF */, {0x12, 36} /* VELNED */, {0x20, 16} /* TIMEGPS */,
    {0x21, 20} /* TIMEUTC */, {0x32, 12} /* SBAS, no SBAS satellite */};

std::vector<std::uint8_t> cfg_msg(std::uint8_t cls, std::uint8_t id, std::uint8_t rate) {
  return ubx_bytes(0x06, 0x01, {cls, id, rate});
}

// The answer to a command sent at t: the ACK-ACK (1) or ACK-NAK (0) naming class/id within
// 100 ms (the model answers UBLOX_REPLY_DELAY_NS = 5 ms after the command, a few bytes later),
// -1 if none; `replies` gets the other UBX frames of that span.
int answer(ublox_neo6m& d, std::int64_t& t, const std::vector<std::uint8_t>& command,
           std::vector<UbxFrame>* replies = nullptr) {
  const std::int64_t end = send(d, t, command);
  const auto got = items(run(d, t, end + 100 * kMs));
  t = end + 100 * kMs;
  int result = -1;
  for (const auto& it : got) {
    if (!it.ubx) continue;
    const auto& f = it.frame;
    if (f.cls == 0x05 && f.payload.size() == 2 && f.payload[0] == command[2] && f.payload[1] == command[3]) {
      EXPECT_EQ(result, -1) << "answered twice";
      result = f.id == 0x01 ? 1 : f.id == 0x00 ? 0 : -2;
    } else if (replies && f.cls != 0x01) {
      replies->push_back(f);
    }
  }
  return result;
}

// Dilutions of precision from satellites' elevation and azimuth (degrees), computed here apart
// from the model: G rows (-cos el sin az, -cos el cos az, -sin el, 1), Q = (G^T G)^-1 by
// Gauss-Jordan; returns {GDOP, PDOP, TDOP, VDOP, HDOP, NDOP, EDOP}, NAV-DOP's order.
std::vector<double> dops(const std::vector<std::pair<int, int>>& sats) {
  double a[4][8] = {};
  for (const auto& [el_deg, az_deg] : sats) {
    const double el = el_deg * kPi / 180, az = az_deg * kPi / 180;
    const double g[4] = {-std::cos(el) * std::sin(az), -std::cos(el) * std::cos(az), -std::sin(el), 1.0};
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) a[r][c] += g[r] * g[c];
  }
  for (int r = 0; r < 4; ++r) a[r][4 + r] = 1.0;
  for (int c = 0; c < 4; ++c) {
    const double p = a[c][c];
    for (int k = 0; k < 8; ++k) a[c][k] /= p;
    for (int r = 0; r < 4; ++r)
      if (r != c) {
        const double f = a[r][c];
        for (int k = 0; k < 8; ++k) a[r][k] -= f * a[c][k];
      }
  }
  const double e = a[0][4], n = a[1][5], u = a[2][6], t = a[3][7];
  return {std::sqrt(e + n + u + t), std::sqrt(e + n + u), std::sqrt(t), std::sqrt(u), std::sqrt(e + n), std::sqrt(n),
          std::sqrt(e)};
}

// WGS-84 geodetic to ECEF (NIMA TR8350.2 eq. 4-14), written here apart from the model.
void to_ecef(double lat_deg, double lon_deg, double h, double out[3]) {
  const double a = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f);
  const double sl = std::sin(lat_deg * kPi / 180), cl = std::cos(lat_deg * kPi / 180);
  const double n = a / std::sqrt(1 - e2 * sl * sl);
  out[0] = (n + h) * cl * std::cos(lon_deg * kPi / 180);
  out[1] = (n + h) * cl * std::sin(lon_deg * kPi / 180);
  out[2] = (n * (1 - e2) + h) * sl;
}

double nmea_degrees(const std::string& value, const std::string& hemisphere) {
  const double v = std::stod(value);
  const double deg = std::floor(v / 100.0);
  const double r = deg + (v - 100.0 * deg) / 60.0;
  return hemisphere == "S" || hemisphere == "W" ? -r : r;
}

}  // namespace

// Every NAV message of the epoch 07:00:03 UTC, field by field: lengths and units as the spec
// gives them, GPS week 2446 and time of week 198021000 ms (2026-11-24 is a Tuesday: 2 days 7 h
// 0 min 3 s + 18 leap seconds into week 2446, counted from 1980-01-06 by hand), and the same
// solution as that epoch's RMC, GGA, GSA and GSV.
TEST(GpsUbx, NavMessagesFieldByFieldAgainstTheNmeaOfTheSameEpoch) {
  auto feed = rover_feed();
  const ublox_neo6m_config c = config(115200);  // fast enough for every message each epoch
  static ublox_neo6m d;
  ublox_neo6m_init(&d, &c, feed.source(), 0);
  line = Line();
  std::int64_t t = 300 * kMs;  // after the banner, before the first epoch (07:00:01)
  items(run(d, 0, t));
  for (const auto& [id, len] : kNavLength) ASSERT_EQ(answer(d, t, cfg_msg(0x01, id, 1)), 1) << int(id);
  ASSERT_EQ(answer(d, t, cfg_msg(0x01, 0x30, 1)), 1);  // SVINFO
  ASSERT_EQ(answer(d, t, ubx_bytes(0x06, 0x01, {0xF0, 0x08, 1})), 1);  // ZDA on as well
  ASSERT_LT(t, 2 * kSecond);
  const auto out = items(run(d, t, 4 * kSecond));

  // The epoch at 07:00:03: its UBX frames and NMEA sentences lie between 3.0 s and 4.0 s.
  std::map<std::uint8_t, std::vector<std::uint8_t>> nav;
  std::map<std::string, std::vector<std::string>> nmea;
  std::vector<std::vector<std::string>> gsv;
  bool nmea_seen = false;
  for (const auto& it : out) {
    if (it.end_ns < 3 * kSecond || it.end_ns >= 4 * kSecond) continue;
    if (it.ubx) {
      ASSERT_EQ(it.frame.cls, 0x01);
      EXPECT_FALSE(nmea_seen) << "UBX after NMEA in one epoch";
      EXPECT_EQ(nav.count(it.frame.id), 0u);
      nav[it.frame.id] = it.frame.payload;
    } else {
      nmea_seen = true;
      const auto f = fields_of(it.text);
      if (f[0] == "GPGSV") gsv.push_back(f);
      else nmea[f[0]] = f;
    }
  }
  for (const auto& [id, len] : kNavLength) {
    ASSERT_EQ(nav.count(id), 1u) << int(id);
    EXPECT_EQ(nav[id].size(), len) << int(id);
  }
  ASSERT_EQ(nav.count(0x30), 1u);
  for (const char* s : {"GPRMC", "GPGGA", "GPGSA", "GPZDA"}) ASSERT_EQ(nmea.count(s), 1u) << s;
  const auto& rmc = nmea["GPRMC"];
  const auto& gga = nmea["GPGGA"];
  const auto& gsa = nmea["GPGSA"];
  EXPECT_EQ(rmc[1], "070003.00");
  EXPECT_EQ(nmea["GPZDA"][2], "24");

  // Time of week in every message; GPS time 18 s ahead of the UTC the NMEA prints.
  for (const auto& [id, p] : nav) EXPECT_EQ(u4(p, 0), 198021000u) << "iTOW of " << int(id);
  const auto& tg = nav[0x20];  // NAV-TIMEGPS: iTOW, fTOW, week, leapS, valid, tAcc
  EXPECT_EQ(i4(tg, 4), 0);
  EXPECT_EQ(i2(tg, 8), 2446);
  EXPECT_EQ(tg[10], 18);
  EXPECT_EQ(tg[11], 0x07);  // towValid, weekValid, leapSValid
  const auto& tu = nav[0x21];  // NAV-TIMEUTC: iTOW, tAcc, nano, year, month, day, hour, min, sec, valid
  EXPECT_EQ(i4(tu, 8), 0);
  EXPECT_EQ(u2(tu, 12), 2026);
  EXPECT_EQ(std::vector<int>(tu.begin() + 14, tu.begin() + 19), (std::vector<int>{11, 24, 7, 0, 3}));
  EXPECT_EQ(tu[19], 0x07);  // validTOW, validWKN, validUTC

  // NAV-POSLLH: lon, lat (1e-7 deg), height above ellipsoid and MSL (mm), hAcc, vAcc (mm).
  const auto& ll = nav[0x02];
  const double lon = i4(ll, 4) * 1e-7, lat = i4(ll, 8) * 1e-7, height = i4(ll, 12) * 1e-3, msl = i4(ll, 16) * 1e-3;
  // GGA prints minutes to 1e-5 (8.3e-8 deg) and POSLLH rounds to 1e-7 deg: both halves together.
  const double angle_tol = 0.5e-5 / 60 + 0.5e-7;
  EXPECT_NEAR(lat, nmea_degrees(gga[2], gga[3]), angle_tol);
  EXPECT_NEAR(lon, nmea_degrees(gga[4], gga[5]), angle_tol);
  EXPECT_NEAR(msl, std::stod(gga[9]), 0.05 + 0.0005);  // GGA to 0.1 m, POSLLH to 1 mm
  EXPECT_NEAR(height - msl, kGeoid, 0.001);            // two roundings of 0.5 mm
  EXPECT_EQ(u4(ll, 20), static_cast<std::uint32_t>(std::lround(std::sqrt(2.0) * d.error.sigma_horizontal_m * 1e3)));
  EXPECT_EQ(u4(ll, 24), static_cast<std::uint32_t>(std::lround(d.error.sigma_vertical_m * 1e3)));
  // The truth at 3 s: 9 m east, 0.3 m up of the origin; within 4.5 sigma of the error
  // (Rayleigh tail exp(-4.5^2/2) = 4e-5 horizontally).
  const gnss_fix_truth truth = sear::GnssTruth(kOrigin, kGeoid).at(3 * kSecond, {9.0, 0.0, 0.3}, {3.0, 0.0, 0.1});
  const sear::Enu off = sear::LocalTangentPlane({truth.latitude_deg, truth.longitude_deg, 0.0}).to_enu({lat, lon, 0.0});
  EXPECT_LT(std::hypot(off.east_m, off.north_m), 4.5 * d.error.sigma_horizontal_m);
  EXPECT_NEAR(msl, truth.altitude_msl_m, 4.5 * d.error.sigma_vertical_m);

  // NAV-SOL: iTOW, fTOW, week, gpsFix, flags, ECEF position (cm), pAcc, ECEF velocity (cm/s),
  // sAcc, pDOP, reserved, numSV, reserved.
  const auto& sol = nav[0x06];
  EXPECT_EQ(i4(sol, 4), 0);
  EXPECT_EQ(i2(sol, 8), 2446);
  EXPECT_EQ(sol[10], 0x03);  // 3D fix
  EXPECT_EQ(sol[11], 0x0D);  // GPSfixOK, WKNSET, TOWSET
  double ecef[3];
  to_ecef(lat, lon, height, ecef);
  // ECEF to 1 cm (0.5 cm per axis) against a position rounded to 1e-7 deg (1.1 cm) and 1 mm.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(i4(sol, 12 + 4 * k) * 0.01, ecef[k], 0.005 + 0.012) << k;
  const double h_acc = std::sqrt(2.0) * d.error.sigma_horizontal_m, v_acc = d.error.sigma_vertical_m;
  EXPECT_EQ(u4(sol, 24), static_cast<std::uint32_t>(std::lround(std::hypot(h_acc, v_acc) * 100)));
  EXPECT_EQ(u2(sol, 44), std::lround(std::stod(gsa[15]) * 100));  // PDOP as GSA prints it
  EXPECT_EQ(sol[47], std::stoi(gga[7]));                           // satellites used as GGA
  EXPECT_EQ(u4(sol, 40), static_cast<std::uint32_t>(std::lround(std::sqrt(3.0) * 0.1 * 100)));  // 3D of 0.1 m/s

  // NAV-POSECEF and NAV-VELECEF carry NAV-SOL's numbers.
  const auto& pe = nav[0x01];
  const auto& ve = nav[0x11];
  EXPECT_TRUE(std::equal(pe.begin() + 4, pe.end(), sol.begin() + 12));
  EXPECT_TRUE(std::equal(ve.begin() + 4, ve.begin() + 16, sol.begin() + 28));
  EXPECT_EQ(u4(ve, 16), u4(sol, 40));

  // NAV-VELNED: velN, velE, velD, speed (3D), gSpeed, heading (1e-5 deg), sAcc, cAcc.
  const auto& vn = nav[0x12];
  const double vel_n = i4(vn, 4) * 0.01, vel_e = i4(vn, 8) * 0.01, vel_d = i4(vn, 12) * 0.01;
  const double g_speed = u4(vn, 20) * 0.01, heading = i4(vn, 24) * 1e-5;
  // RMC speed to 0.001 kn (0.26 mm/s) and course to 0.01 deg; VELNED to 1 cm/s and 1e-5 deg.
  EXPECT_NEAR(g_speed, std::stod(rmc[7]) * 1852.0 / 3600.0, 0.005 + 0.0003);
  EXPECT_NEAR(heading, std::stod(rmc[8]), 0.005 + 0.5e-5);
  EXPECT_NEAR(std::hypot(vel_n, vel_e), g_speed, 0.01);           // three 0.5 cm/s roundings
  EXPECT_NEAR(u4(vn, 16) * 0.01, std::hypot(g_speed, vel_d), 0.01);
  EXPECT_NEAR(std::atan2(vel_e, vel_n) * 180 / kPi, heading, std::atan(0.01 / g_speed) * 180 / kPi);
  EXPECT_NEAR(vel_d, -0.1, 4.5 * 0.1);  // climbing 0.1 m/s; velocity noise 0.1 m/s per axis
  // Heading accuracy: a 0.1 m/s cross-track error turns a 3 m/s track by 0.1/3 rad.
  const double c_acc = 0.1 / g_speed * 180 / kPi;
  EXPECT_NEAR(u4(vn, 32) * 1e-5, c_acc, c_acc * 0.005 / g_speed + 1e-5);  // gSpeed printed to 1 cm/s
  // The ECEF velocity is the NED one turned to the earth frame at (lat, lon).
  const double sl = std::sin(lat * kPi / 180), cl = std::cos(lat * kPi / 180);
  const double so = std::sin(lon * kPi / 180), co = std::cos(lon * kPi / 180);
  const double up = -vel_d;
  const double v_ecef[3] = {-so * vel_e - sl * co * vel_n + cl * co * up, co * vel_e - sl * so * vel_n + cl * so * up,
                            cl * vel_n + sl * up};
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(i4(sol, 28 + 4 * k) * 0.01, v_ecef[k], 0.015) << k;  // 0.5 cm/s x 3

  // NAV-STATUS: iTOW, gpsFix, flags, fixStat, flags2, ttff, msss. The first fix came with the
  // first epoch, 07:00:01, one second after power-on; this epoch is three seconds after it.
  const auto& st = nav[0x03];
  EXPECT_EQ(st[4], 0x03);
  EXPECT_EQ(st[5], 0x0D);
  EXPECT_EQ(u4(st, 8), 1000u);
  EXPECT_EQ(u4(st, 12), 3000u);

  // NAV-SVINFO: iTOW, numCh, globalFlags (chipGen 2 = u-blox 6), then 12 bytes a channel: chn,
  // svid, flags (bit 0 svUsed), quality, cno, elev, azim, prRes. Against GSV and GSA.
  const auto& sv = nav[0x30];
  const int channels = sv[4];
  ASSERT_EQ(sv.size(), 8u + 12u * static_cast<unsigned>(channels));
  EXPECT_EQ(sv[5] & 0x07, 2);
  ASSERT_FALSE(gsv.empty());
  EXPECT_EQ(channels, std::stoi(gsv[0][3]));  // satellites in view
  std::map<int, std::vector<int>> listed;      // GSV: prn -> elevation, azimuth, SNR
  for (const auto& s : gsv)
    for (std::size_t k = 4; k + 3 < s.size(); k += 4)
      listed[std::stoi(s[k])] = {std::stoi(s[k + 1]), std::stoi(s[k + 2]), std::stoi(s[k + 3])};
  std::set<int> gsa_used;
  for (int k = 3; k < 15; ++k)
    if (!gsa[static_cast<std::size_t>(k)].empty()) gsa_used.insert(std::stoi(gsa[static_cast<std::size_t>(k)]));
  std::set<int> used;
  std::vector<std::pair<int, int>> geometry;
  for (int ch = 0; ch < channels; ++ch) {
    const std::size_t o = 8 + 12 * static_cast<std::size_t>(ch);
    const int prn = sv[o + 1];
    ASSERT_EQ(listed.count(prn), 1u) << prn;
    EXPECT_EQ(sv[o], ch);
    EXPECT_EQ(sv[o + 4], listed[prn][2]);                      // C/N0 as GSV's SNR
    EXPECT_EQ(static_cast<std::int8_t>(sv[o + 5]), listed[prn][0]);
    EXPECT_EQ(i2(sv, o + 6), listed[prn][1]);
    if (sv[o + 2] & 0x01) {
      used.insert(prn);
      geometry.emplace_back(static_cast<std::int8_t>(sv[o + 5]), i2(sv, o + 6));
      EXPECT_GE(sv[o + 3], 5);  // code and carrier locked
    }
  }
  EXPECT_EQ(used, gsa_used);
  EXPECT_EQ(static_cast<int>(used.size()), sol[47]);

  // NAV-DOP (0.01 units): GDOP, PDOP, TDOP, VDOP, HDOP, NDOP, EDOP of the satellites SVINFO marks
  // used, recomputed here; PDOP, HDOP, VDOP as GSA prints them. One unit of rounding.
  const auto& dp = nav[0x04];
  const auto want = dops(geometry);
  for (int k = 0; k < 7; ++k) EXPECT_NEAR(u2(dp, 4 + 2 * static_cast<std::size_t>(k)) * 0.01, want[static_cast<std::size_t>(k)], 0.0051) << k;
  EXPECT_EQ(u2(dp, 6), std::lround(std::stod(gsa[15]) * 100));
  EXPECT_EQ(u2(dp, 12), std::lround(std::stod(gsa[16]) * 100));
  EXPECT_EQ(u2(dp, 10), std::lround(std::stod(gsa[17]) * 100));

  // NAV-SBAS: iTOW, geo, mode, sys, service, cnt: SBAS enabled (the default), no SBAS satellite.
  const auto& sb = nav[0x32];
  EXPECT_EQ(sb[4], 0);
  EXPECT_EQ(sb[5], 1);
  EXPECT_EQ(static_cast<std::int8_t>(sb[6]), -1);
  EXPECT_EQ(sb[8], 0);
}

// Before the first fix the NAV messages say so: no fix, no valid time, position fields zero,
// accuracies unknown; satellites being acquired have no orbit yet.
TEST(GpsUbx, NoFixBeforeTheTimeToFirstFix) {
  auto feed = rover_feed();
  ublox_neo6m_config c = config(115200);
  c.error.ttff_s = 27.0;  // NEO-6 datasheet cold start
  static ublox_neo6m d;
  ublox_neo6m_init(&d, &c, feed.source(), 0);
  line = Line();
  std::int64_t t = 300 * kMs;
  items(run(d, 0, t));  // the banner
  for (int id : {0x02, 0x03, 0x06, 0x20, 0x30})
    ASSERT_EQ(answer(d, t, cfg_msg(0x01, static_cast<std::uint8_t>(id), 1)), 1);
  std::map<std::uint8_t, std::vector<std::uint8_t>> nav;
  for (const auto& it : items(run(d, t, 5 * kSecond)))
    if (it.ubx && it.end_ns >= 4 * kSecond) nav[it.frame.id] = it.frame.payload;
  ASSERT_EQ(nav.size(), 5u);
  EXPECT_EQ(nav[0x06][10], 0x00);  // no fix
  EXPECT_EQ(nav[0x06][11], 0x00);  // no flags
  EXPECT_EQ(nav[0x06][47], 0);
  EXPECT_EQ(i4(nav[0x02], 8), 0);
  EXPECT_EQ(u4(nav[0x02], 20), 0xFFFFFFFFu);
  EXPECT_EQ(nav[0x03][4], 0x00);
  EXPECT_EQ(u4(nav[0x03], 8), 0u);  // no ttff yet
  EXPECT_EQ(nav[0x20][11], 0x00);   // time not valid
  // 4 s after power-on: first satellite at 2 s, one more every 0.5 s (gnss_error.h): 5 tracked.
  EXPECT_EQ(nav[0x30][4], 5);
  for (int ch = 0; ch < 5; ++ch) EXPECT_EQ(nav[0x30][8 + 12 * static_cast<std::size_t>(ch) + 2], 0x00);  // not used, no orbit
}

// Each CFG message with the answer a u-blox 6 gives, and the refusals: CFG-RATE with navRate
// other than 1 (the spec: fixed at 1 on u-blox 5 and 6), including gpsd 3.22's own CFG-RATE,
// whose navRate bytes 00 01 read little-endian as 256; measRate faster than the model's 100 ms
// and zero; timeRef other than UTC (0) or GPS (1). A refused command changes nothing.
TEST(GpsUbx, EachCfgIsAcknowledgedOrRefusedAsAUblox6Does) {
  auto feed = rover_feed();
  const ublox_neo6m_config c = config(115200);
  static ublox_neo6m d;
  ublox_neo6m_init(&d, &c, feed.source(), 0);
  line = Line();
  std::int64_t t = 300 * kMs;
  items(run(d, 0, t));  // the banner
  auto rate_now = [&]() {
    std::vector<UbxFrame> r;
    EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x08, {}), &r), 1);
    EXPECT_EQ(r.size(), 1u);
    return r.empty() ? std::vector<std::uint8_t>{} : r[0].payload;
  };
  const std::vector<std::uint8_t> default_rate = {0xE8, 0x03, 0x01, 0x00, 0x01, 0x00};  // 1000 ms, 1, GPS
  EXPECT_EQ(rate_now(), default_rate);
  const std::vector<std::vector<std::uint8_t>> refused = {
      {0xE8, 0x03, 0x02, 0x00, 0x01, 0x00},  // navRate 2
      {0xE8, 0x03, 0x00, 0x00, 0x01, 0x00},  // navRate 0
      {0x03, 0xE8, 0x00, 0x01, 0x00, 0x00},  // gpsd's ubx_rate(): navRate 0x0100
      {0x63, 0x00, 0x01, 0x00, 0x01, 0x00},  // measRate 99 ms, one below the fastest
      {0x00, 0x00, 0x01, 0x00, 0x01, 0x00},  // measRate 0
      {0xE8, 0x03, 0x01, 0x00, 0x02, 0x00},  // timeRef 2
  };
  for (const auto& p : refused) {
    EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x08, p)), 0);
    EXPECT_EQ(rate_now(), default_rate);
  }
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x08, {0xE8, 0x03, 0x01, 0x00})), 0);  // 4 bytes: not CFG-RATE
  // The fastest accepted: 100 ms, UTC-aligned; NAV-TIMEGPS then comes every 100 ms.
  const std::vector<std::uint8_t> fastest = {0x64, 0x00, 0x01, 0x00, 0x00, 0x00};
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x08, fastest)), 1);
  EXPECT_EQ(rate_now(), fastest);
  EXPECT_EQ(answer(d, t, cfg_msg(0x01, 0x20, 1)), 1);
  std::vector<std::uint32_t> tow;
  for (const auto& it : items(run(d, t, t + kSecond)))
    if (it.ubx && it.frame.id == 0x20) tow.push_back(u4(it.frame.payload, 0));
  ASSERT_GE(tow.size(), 9u);
  for (std::size_t i = 1; i < tow.size(); ++i) EXPECT_EQ(tow[i] - tow[i - 1], 100u);
  t += kSecond;

  // CFG-MSG: NAV messages a u-blox 6 has (3- and 8-byte forms, polled back with the rate in
  // UART1's slot); those it has not (NAV-PVT 01 07 and NAV-SAT 01 35 came with u-blox 7 and 8,
  // NAV-TIMELS 01 26 and NAV-EOE 01 61 with u-blox 8); NMEA GST the model does not print: off is
  // accepted, on is refused.
  EXPECT_EQ(answer(d, t, cfg_msg(0x01, 0x06, 1)), 1);
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x01, {0x01, 0x30, 0, 5, 0, 0, 0, 0})), 1);
  std::vector<UbxFrame> r;
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x01, {0x01, 0x30}), &r), 1);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].payload, (std::vector<std::uint8_t>{0x01, 0x30, 0, 5, 0, 0, 0, 0}));
  for (int id : {0x07, 0x35, 0x26, 0x61})
    EXPECT_EQ(answer(d, t, cfg_msg(0x01, static_cast<std::uint8_t>(id), 1)), 0) << id;
  EXPECT_EQ(answer(d, t, cfg_msg(0xF0, 0x07, 0)), 1);
  EXPECT_EQ(answer(d, t, cfg_msg(0xF0, 0x07, 1)), 0);
  EXPECT_EQ(answer(d, t, cfg_msg(0x02, 0x10, 1)), 0);  // RXM-RAW: not modelled

  // CFG-NAV5: dynModel 4 (automotive) with mask bit 0 only; polled back with the defaults kept
  // (fixMode 3, minElev 5, pDop 25.0, tDop 25.0, pAcc 100 m, tAcc 300 m). dynModel 1 is reserved,
  // fixMode 4 does not exist, a 35-byte payload is no CFG-NAV5.
  std::vector<std::uint8_t> nav5(36, 0);
  nav5[0] = 0x01;
  nav5[2] = 4;
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x24, nav5)), 1);
  r.clear();
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x24, {}), &r), 1);
  ASSERT_EQ(r.size(), 1u);
  ASSERT_EQ(r[0].payload.size(), 36u);
  EXPECT_EQ(r[0].payload[2], 4);
  EXPECT_EQ(r[0].payload[3], 3);
  EXPECT_EQ(r[0].payload[12], 5);
  EXPECT_EQ(u2(r[0].payload, 14), 250);
  EXPECT_EQ(u2(r[0].payload, 16), 250);
  EXPECT_EQ(u2(r[0].payload, 18), 100);
  EXPECT_EQ(u2(r[0].payload, 20), 300);
  nav5[2] = 1;
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x24, nav5)), 0);
  nav5[0] = 0x04;
  nav5[2] = 0;
  nav5[3] = 4;
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x24, nav5)), 0);
  nav5.pop_back();
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x24, nav5)), 0);

  // CFG-SBAS: off, polled back; NAV-SBAS then reports mode 0 (disabled).
  const std::vector<std::uint8_t> sbas_off = {0x00, 0x03, 3, 0, 0, 0, 0, 0};
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x16, sbas_off)), 1);
  r.clear();
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x16, {}), &r), 1);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].payload, sbas_off);
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x16, {0x00, 0x03, 3})), 0);

  // CFG-CFG save (12 bytes) and with a device mask (13): accepted.
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x09, std::vector<std::uint8_t>(12, 0))), 1);
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x09, std::vector<std::uint8_t>(13, 0))), 1);

  // MON-VER poll: swVersion CH[30], hwVersion CH[10], ROM version CH[30], NUL-padded; no ACK.
  r.clear();
  EXPECT_EQ(answer(d, t, ubx_bytes(0x0A, 0x04, {}), &r), -1);
  ASSERT_EQ(r.size(), 1u);
  const auto& ver = r[0].payload;
  ASSERT_EQ(ver.size(), 70u);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(ver.data())), "7.03 (45969)");
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(ver.data() + 30)), "00040007");
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(ver.data() + 40)), "7.03 (45969)");
  EXPECT_EQ(ver[29], 0);
  EXPECT_EQ(ver[39], 0);
  EXPECT_EQ(ver[69], 0);

  // A NAV poll gets the latest epoch's message, with no ACK; NAV-SBAS now says disabled.
  const std::int64_t poll_end = send(d, t, ubx_bytes(0x01, 0x32, {}));
  std::vector<UbxFrame> polled;
  for (const auto& it : items(run(d, t, poll_end + 50 * kMs))) {
    if (it.ubx && it.frame.cls == 0x01 && it.frame.id == 0x32) polled.push_back(it.frame);
    EXPECT_FALSE(it.ubx && it.frame.cls == 0x05) << "a poll is not acknowledged";
  }
  ASSERT_EQ(polled.size(), 1u);
  EXPECT_EQ(polled[0].payload[5], 0);
  t = poll_end + 50 * kMs;

  // CFG-PRT rates and framing the NEO-6 UART does not offer (230400 baud above its 115200; 7N1,
  // charLen 10): refused, the port unchanged.
  std::vector<std::uint8_t> fast_prt = {1, 0, 0, 0, 0xD0, 0x08, 0, 0, 0x00, 0x84, 0x03, 0x00, 0x07, 0, 0x03, 0, 0, 0, 0, 0};
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x00, fast_prt)), 0);
  std::vector<std::uint8_t> seven = {1, 0, 0, 0, 0x90, 0x08, 0, 0, 0x00, 0xC2, 0x01, 0x00, 0x07, 0, 0x03, 0, 0, 0, 0, 0};
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x00, seven)), 0);
  EXPECT_EQ(ublox_neo6m_baud(&d), 115200u);

  // gpsd's CFG-PRT for binary mode: UART1, 8N1 (0x08D0 with the Antaris bit), 115200, in
  // UBX+NMEA+RTCM, out UBX only: ACK, then no NMEA, only UBX.
  std::vector<std::uint8_t> prt = {1, 0, 0, 0, 0xD0, 0x08, 0, 0, 0x00, 0xC2, 0x01, 0x00, 0x07, 0, 0x01, 0, 0, 0, 0, 0};
  EXPECT_EQ(answer(d, t, ubx_bytes(0x06, 0x00, prt)), 1);
  bool any_ubx = false;
  for (const auto& it : items(run(d, t, t + 2 * kSecond))) {
    EXPECT_TRUE(it.ubx) << it.text;
    any_ubx = any_ubx || it.ubx;
  }
  EXPECT_TRUE(any_ubx);
  // Refused above: six CFG-RATE and a short one, four NAV ids, GST on, RXM-RAW, three CFG-NAV5,
  // a short CFG-SBAS, two CFG-PRT.
  EXPECT_EQ(d.naks, 6u + 1u + 4u + 1u + 1u + 3u + 1u + 2u);
}

// UBX and NMEA share the port: at 9600 baud (960 bytes a second) with every NAV message (478
// bytes an epoch) and the default NMEA set at 2 Hz the receiver is asked for about twice what the
// line carries, drops whole
// messages, never cuts one, and never puts more on the line than the baud allows. CFG-MSG rate 2
// gives a message every second epoch, as for NMEA.
TEST(GpsUbx, UbxAndNmeaShareThePortsBandwidthAndTheRates) {
  auto feed = rover_feed();
  const ublox_neo6m_config c = config(9600);
  static ublox_neo6m d;
  ublox_neo6m_init(&d, &c, feed.source(), 0);
  line = Line();
  std::int64_t t = 300 * kMs;
  items(run(d, 0, t));  // the banner
  // Sent back to back, acknowledged in turn (at 9600 baud an answer may wait behind a cycle).
  std::int64_t end = t;
  for (const auto& [id, len] : kNavLength) end = send(d, end, cfg_msg(0x01, id, 1));
  end = send(d, end, cfg_msg(0x01, 0x30, 1));
  end = send(d, end, ubx_bytes(0x06, 0x08, {0xF4, 0x01, 1, 0, 1, 0}));  // 500 ms
  ASSERT_LT(end, kSecond);
  const std::int64_t from = 2 * kSecond, to = 7 * kSecond;
  const auto bytes = run(d, t, to);
  EXPECT_EQ(d.acks, 12u);
  EXPECT_EQ(d.naks, 0u);
  std::size_t in_span = 0;
  for (std::size_t i = 1; i < bytes.size(); ++i) ASSERT_GE(bytes[i].end_ns - bytes[i - 1].end_ns, serial_frame_ns(9600));
  for (const auto& b : bytes) in_span += b.end_ns >= from && b.end_ns < to;
  EXPECT_LE(in_span, 5u * 960u);  // at most one byte per frame time
  EXPECT_GE(in_span, 5u * 960u - 5u * 960u / 10u);  // and the line is kept busy (at least 90 %)
  EXPECT_GT(d.tx.dropped_bytes, 0u);
  int ubx = 0, nmea = 0;
  for (const auto& it : items(bytes)) (it.ubx ? ubx : nmea) += it.end_ns >= from;
  EXPECT_GT(ubx, 0);
  EXPECT_GT(nmea, 0);

  // Rate 2 for NAV-SOL at 1 Hz and 115200 baud: 5 of 10 epochs; NAV-POSLLH at rate 1: 10.
  const ublox_neo6m_config fast = config(115200);
  ublox_neo6m_init(&d, &fast, feed.source(), 0);
  line = Line();
  t = 300 * kMs;
  ASSERT_EQ(answer(d, t, cfg_msg(0x01, 0x06, 2)), 1);
  ASSERT_EQ(answer(d, t, cfg_msg(0x01, 0x02, 1)), 1);
  int sol = 0, llh = 0;
  for (const auto& it : items(run(d, t, 10 * kSecond + 500 * kMs)))
    if (it.ubx && it.frame.cls == 0x01) (it.frame.id == 0x06 ? sol : llh) += 1;
  EXPECT_EQ(llh, 10);
  EXPECT_EQ(sol, 5);
  EXPECT_EQ(d.tx.dropped_bytes, 0u);
}

// NAV-VELNED carries the velocity error of the model in all three axes: over 300 epochs at 10 Hz
// (a fresh draw every 100 ms tick, so independent) the sample sd of velE, velN and velD about the
// truth (3, 0, -0.1 m/s) is the configured 0.1 m/s. Its relative standard error is 1/sqrt(2 x 300)
// = 4 %; 20 % bounds (with the 1 cm/s print step adding 0.3 cm/s in quadrature) fail only a wrong
// model.
TEST(GpsUbx, VelnedCarriesTheConfiguredVelocityErrorOnEachAxis) {
  auto feed = rover_feed();
  const ublox_neo6m_config c = config(115200);
  static ublox_neo6m d;
  ublox_neo6m_init(&d, &c, feed.source(), 0);
  line = Line();
  std::int64_t t = 300 * kMs;
  items(run(d, 0, t));  // the banner
  ASSERT_EQ(answer(d, t, ubx_bytes(0x06, 0x08, {100, 0, 1, 0, 1, 0})), 1);
  ASSERT_EQ(answer(d, t, cfg_msg(0x01, 0x12, 1)), 1);
  std::vector<double> e, n, down;
  for (const auto& it : items(run(d, t, t + 30 * kSecond)))
    if (it.ubx && it.frame.cls == 0x01 && it.frame.id == 0x12) {
      n.push_back(i4(it.frame.payload, 4) * 0.01);
      e.push_back(i4(it.frame.payload, 8) * 0.01 - 3.0);
      down.push_back(i4(it.frame.payload, 12) * 0.01 + 0.1);
    }
  ASSERT_GE(n.size(), 290u);
  auto sd = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x * x;
    return std::sqrt(s / static_cast<double>(v.size()));
  };
  for (const auto* axis : {&e, &n, &down})
    EXPECT_NEAR(sd(*axis), GNSS_DEFAULT_VELOCITY_SD_MPS, 0.2 * GNSS_DEFAULT_VELOCITY_SD_MPS);
}
