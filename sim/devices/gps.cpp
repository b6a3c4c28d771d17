// GPS receivers on a UART: a u-blox NEO-6M (NMEA, UBX configuration) and a MediaTek MT3339 (NMEA,
// PMTK commands), talking from the simulator's process. Their fixes come from the antenna's true
// position and velocity, through WGS-84 geodesy and the receiver's error model.
#include <fmt/format.h>

#include <cmath>
#include <ctime>

#include "devices/device_kinds.hpp"
#include "devices/sim_device.hpp"
#include "devices/uart_device.hpp"
#include "sensors/gnss_truth.hpp"

extern "C" {
#include "devices/mtk3339.h"
#include "devices/ublox_neo6m.h"
}

namespace sear {
namespace {

const Range kRate = Range::between(1, 10, "1..10 Hz");
const Range kBaud = Range::between(4800, 115200, "4800..115200");
const Range kCep = Range::above(0, 1000, "> 0 and <= 1000 m");
const Range kTtff = Range::between(0, 3600, "0..3600 s");
const Range kGeoid = Range::between(-110, 90, "-110..90 m (the geoid's extremes)");

// "2026-06-01T12:00:00Z" -> seconds since 1970, or -1.
std::int64_t parse_utc(const std::string& text) {
  std::tm tm{};
  char z = 0;
  if (std::sscanf(text.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d%c", &tm.tm_year, &tm.tm_mon, &tm.tm_mday, &tm.tm_hour,
                  &tm.tm_min, &tm.tm_sec, &z) != 7 || z != 'Z')
    return -1;
  tm.tm_year -= 1900;
  tm.tm_mon -= 1;
  const std::time_t t = timegm(&tm);
  return t < 0 ? -1 : static_cast<std::int64_t>(t);
}

void check_utc(const DeviceDesc& d, ElementReader& r) {
  if (parse_utc(d.text("utc_start")) < 0)
    r.error(fmt::format("<{}> utc_start '{}' is not a UTC time like 2026-06-01T12:00:00Z", d.kind->element,
                        d.text("utc_start")));
}

gnss_error_config error_config(const DeviceDesc& d, DeviceHost& host) {
  gnss_error_config e{};
  e.cep_m = d.value("cep");
  e.vertical_sd_m = -1;  // from the satellites' VDOP
  e.velocity_sd_mps = d.value("velocity_sd");
  e.correlation_s = -1;
  e.ttff_s = d.value("ttff");
  e.seed = host.seed(0);
  return e;
}

// The talker's own model in C; Traits names its functions.
template <class Traits>
class Gps : public SimDevice, public UartDevice {
 public:
  Gps(const DeviceDesc& d, DeviceHost& host)
      : antenna_m_(d.position_m),
        feed_(GnssTruth(host.world().gps_origin, d.value("geoid_separation")),
              [this](std::int64_t, Enu& position, Enu& velocity) { antenna_state(position, velocity); }) {
    typename Traits::Config c;
    Traits::defaults(&c);
    c.rate_hz = d.value("rate_hz");
    c.baud = static_cast<std::uint32_t>(d.value("baud"));
    c.utc_start_s = parse_utc(d.text("utc_start"));
    c.error = error_config(d, host);
    Traits::init(&model_, &c, feed_.source(), 0);
  }

  void sample(const SenseContext& c, SampleSink&) override { context_ = &c; }

  UartDevice* uart() override { return this; }
  void receive(const serial_byte& byte) override { Traits::receive(&model_, &byte); }
  std::size_t transmit(std::int64_t now_ns, std::int64_t until_ns, serial_byte* out, std::size_t cap) override {
    return Traits::transmit(&model_, now_ns, until_ns, out, cap);
  }
  std::uint32_t baud() const override { return Traits::baud(&model_); }

 private:
  // The antenna as the world is at the start of the quantum in which the fix goes out.
  void antenna_state(Enu& position, Enu& velocity) const {
    const dBodyID body = context_->chassis;
    dVector3 p, v;
    dBodyGetRelPointPos(body, antenna_m_.x(), antenna_m_.y(), antenna_m_.z(), p);
    dBodyGetRelPointVel(body, antenna_m_.x(), antenna_m_.y(), antenna_m_.z(), v);
    position = {p[0], p[1], p[2]};
    velocity = {v[0], v[1], v[2]};
  }

  Eigen::Vector3d antenna_m_;
  GnssTruthFeed feed_;
  typename Traits::Model model_{};
  const SenseContext* context_ = nullptr;  // set each quantum before the bridge asks for bytes
};

// Each talker's C functions by the same names, so that Gps<> serves both; the two models share
// one shape of API and differ only in their prefix.
#define SEAR_GPS_TRAITS(Name, prefix)                                                                     \
  struct Name {                                                                                           \
    using Config = prefix##_config;                                                                       \
    using Model = prefix;                                                                                 \
    static void defaults(Config* c) { prefix##_defaults(c); }                                            \
    static void init(Model* m, const Config* c, gnss_truth_source s, std::int64_t t) { prefix##_init(m, c, s, t); } \
    static void receive(Model* m, const serial_byte* b) { prefix##_receive(m, b); }                      \
    static std::size_t transmit(Model* m, std::int64_t now, std::int64_t until, serial_byte* out, std::size_t cap) { \
      return prefix##_transmit(m, now, until, out, cap);                                                  \
    }                                                                                                     \
    static std::uint32_t baud(const Model* m) { return prefix##_baud(m); }                               \
  };
SEAR_GPS_TRAITS(Ublox, ublox_neo6m)
SEAR_GPS_TRAITS(Mtk, mtk3339)
#undef SEAR_GPS_TRAITS

std::vector<DeviceParam> gps_params(double ttff_s) {
  using T = DeviceParam::Type;
  return {{"rate_hz", T::Number, 1, kRate, "Hz", "navigation rate at power-up (the firmware may change it)"},
          {"baud", T::Whole, 9600, kBaud, "", "its UART's rate at power-up"},
          {"utc_start", T::Name, 0, {}, "", "UTC at power-on", {}, 1, "2026-06-01T12:00:00Z"},
          {"cep", T::Number, GNSS_DEFAULT_CEP_M, kCep, "m", "horizontal accuracy: half of all fixes lie within this"},
          {"velocity_sd", T::Number, GNSS_DEFAULT_VELOCITY_SD_MPS, {0, 10, false, "0..10 m/s"}, "m/s",
           "standard deviation of each velocity component"},
          {"ttff", T::Number, ttff_s, kTtff, "s", "time to first fix from power-on"},
          {"geoid_separation", T::Number, 0, kGeoid, "m",
           "the geoid's height above the WGS-84 ellipsoid at the origin (EGM96), for MSL altitudes"}};
}

}  // namespace

const DeviceKind& ublox_neo6m_kind() {
  static const DeviceKind kind{
      "ublox_neo6m", "u-blox NEO-6M GPS: NMEA 0183 and UBX NAV at 9600 baud; UBX CFG-PRT/RATE/MSG/NAV5/SBAS, MON-VER and NAV polls answered", Mount::PositionYaw, 0,
      {{"uart", WireKind::UartPort, true, "the UART its TX and RX are wired to"}},
      gps_params(GNSS_DEFAULT_TTFF_S),
      [](const DeviceDesc& d, DeviceHost& h) -> std::unique_ptr<SimDevice> { return std::make_unique<Gps<Ublox>>(d, h); },
      check_utc};
  return kind;
}

const DeviceKind& mtk3339_kind() {
  static const DeviceKind kind{
      "mtk3339", "MediaTek MT3339 GPS (PA6H modules): NMEA 0183 at 9600 baud, PMTK220/314 accepted", Mount::PositionYaw, 0,
      {{"uart", WireKind::UartPort, true, "the UART its TX and RX are wired to"}},
      gps_params(GNSS_DEFAULT_TTFF_S),
      [](const DeviceDesc& d, DeviceHost& h) -> std::unique_ptr<SimDevice> { return std::make_unique<Gps<Mtk>>(d, h); },
      check_utc};
  return kind;
}

}  // namespace sear
