// SICK LMS200 / LMS291 laser scanner on a UART: the telegram protocol runs in the simulator's
// process (hal/devices/sick_lms2xx), which asks for a scan only when it will send one; the scan
// is a planar fan cast against the one world from the scanner's pose.
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>

#include "devices/device_kinds.hpp"
#include "devices/sim_device.hpp"
#include "devices/uart_device.hpp"
#include "scene/value_ranges.hpp"
#include "sensors/range_sensor.hpp"

extern "C" {
#include "devices/sick_lms2xx.h"
}

namespace sear {
namespace {

// The longest distance any range mode reports: 8191 cm less the error codes at the top.
constexpr double kMaxRangeM = 81.91;
// Power-up time: from a few to tens of seconds on real units; long enough for a firmware to be
// listening, short enough not to dominate a test.
const Range kPowerUp = Range::between(0, 60, "0..60 s");

class Lms2xx : public SimDevice, public UartDevice {
 public:
  Lms2xx(const DeviceDesc& d, DeviceHost& host) : position_m_(d.position_m), yaw_rad_(d.yaw_rad) {
    lms2xx_config config;
    lms2xx_default_config(&config);
    const char* type = d.value("type") == 0 ? "LMS200;30106" : "LMS291;S05";
    std::strncpy(config.type, type, LMS2XX_TYPE_CHARS);
    config.seed = host.seed(0);
    config.power_up_ns = std::llround(d.value("power_up") * 1e9);
    config.noise_sd_mm_mode_m = d.value("noise_mm_mode");
    config.noise_sd_cm_mode_m = d.value("noise_cm_mode");
    lms2xx_init(&lms_, &config, {&Lms2xx::measure, this}, 0);
  }

  void sample(const SenseContext& c, SampleSink&) override { context_ = &c; }

  UartDevice* uart() override { return this; }
  void receive(const serial_byte& byte) override { lms2xx_receive(&lms_, &byte); }
  std::size_t transmit(std::int64_t now_ns, std::int64_t until_ns, serial_byte* out, std::size_t cap) override {
    return lms2xx_transmit(&lms_, now_ns, until_ns, out, cap);
  }
  std::uint32_t baud() const override { return lms2xx_baud(&lms_); }
  std::int64_t baud_since_ns() const override { return lms2xx_baud_since_ns(&lms_); }

 private:
  // The model's scan source. Angles are the scanner's (0 its right, pi/2 ahead); the world is as
  // it was at the start of the quantum in which the scan is sent.
  static void measure(void* self, std::int64_t, double first_rad, double step_rad, std::uint32_t count, double* out_m) {
    auto& s = *static_cast<Lms2xx*>(self);
    const SenseContext& c = *s.context_;
    const auto key = std::make_tuple(first_rad, step_rad, count);
    auto it = s.fans_.find(key);
    if (it == s.fans_.end()) {
      ScanFan fan;
      fan.position_m = s.position_m_;
      fan.first_angle_rad = first_rad + s.yaw_rad_;
      fan.step_rad = step_rad;
      fan.count = static_cast<int>(count);
      fan.max_range_m = kMaxRangeM;
      it = s.fans_.emplace(key, RangeScan(fan)).first;
    }
    s.ranges_.resize(count);
    it->second.scan(c.physics, c.chassis, c.self_entity, s.ranges_.data());
    for (std::uint32_t i = 0; i < count; ++i) out_m[i] = s.ranges_[i];
  }

  Eigen::Vector3d position_m_;
  double yaw_rad_;
  lms2xx lms_{};
  const SenseContext* context_ = nullptr;  // set each quantum before the bridge asks for bytes
  std::map<std::tuple<double, double, std::uint32_t>, RangeScan> fans_;  // one per variant and interlace
  std::vector<float> ranges_;
};

}  // namespace

const DeviceKind& lms2xx_kind() {
  static const DeviceKind kind{
      "lms2xx", "SICK LMS200/LMS291 laser scanner: 180 or 100 degree scans, telegrams on a UART (9600 baud at power-up)",
      Mount::PositionYaw, 0,
      {{"uart", WireKind::UartPort, true, "the UART it is connected to (through an RS-232 level converter)"}},
      {{"type", DeviceParam::Type::Choice, 0, {}, "", "the model, as it answers a type request", {"LMS200", "LMS291"}},
       {"power_up", DeviceParam::Type::Number, 5.0, kPowerUp, "s", "from power-on to its power-up telegram"},
       {"noise_mm_mode", DeviceParam::Type::Number, 0.005, ranges::kRangeNoise, "m",
        "standard deviation of a distance in mm mode (datasheet: typ. 5 mm)"},
       {"noise_cm_mode", DeviceParam::Type::Number, 0.01, ranges::kRangeNoise, "m",
        "standard deviation of a distance in cm mode"}},
      [](const DeviceDesc& d, DeviceHost& h) -> std::unique_ptr<SimDevice> { return std::make_unique<Lms2xx>(d, h); }};
  return kind;
}

}  // namespace sear
