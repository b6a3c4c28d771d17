// Sharp GP2D12 (analog) and GP2D15 (digital) infrared rangers: a narrow beam of rays measured
// every 38.3 ms; the transfer curve and the switch run in the firmware's process.
#include <fmt/format.h>

#include <cmath>

#include "devices/device_kinds.hpp"
#include "devices/sim_device.hpp"
#include "scene/value_ranges.hpp"
#include "sensors/range_sensor.hpp"

extern "C" {
#include "devices/sharp_gp2d12.h"
}

namespace sear {
namespace {

class SharpRanger : public SimDevice {
 public:
  SharpRanger(const DeviceDesc& d, DeviceHost& host, bool analog) : sensor_(beam(d)) {
    sear_link_input in = blank_input(analog ? SEAR_INPUT_GP2D12 : SEAR_INPUT_GP2D15);
    if (analog) {
      in.pins[0] = static_cast<std::uint32_t>(d.wire("adc"));
      in.param[0] = d.value("noise_v");
    } else {
      in.pins[0] = static_cast<std::uint32_t>(d.wire("pin"));
      in.param[0] = d.value("switch_distance");
      in.param[1] = d.value("hysteresis");
    }
    input_ = host.add_input(in);
  }

  // Measurements on the sensor's own cycle, k * period; the world between steps is taken as it
  // is at the step's start.
  void sample(const SenseContext& c, SampleSink& sink) override {
    for (std::int64_t k = (c.t0_ns + kPeriod - 1) / kPeriod; k * kPeriod < c.t1_ns; ++k) {
      const RangeReading r = sensor_.measure(c.physics, c.chassis, c.self_entity);
      sink.add(k * kPeriod, static_cast<std::uint64_t>(k), input_, {r.hit ? r.distance_m : INFINITY});
    }
  }

  static RangeBeam beam(const DeviceDesc& d) {
    RangeBeam b;
    b.position_m = d.position_m;
    b.yaw_rad = d.yaw_rad;
    b.pitch_rad = d.pitch_rad;
    b.half_angle_rad = d.value("half_angle_deg");
    b.resolution_rad = d.value("resolution_deg");
    b.max_range_m = d.value("max_range");
    return b;
  }

 private:
  static constexpr std::int64_t kPeriod = GP2D12_PERIOD_NS;  // both parts measure on the same cycle
  RangeSensor sensor_;
  std::uint32_t input_ = 0;
};

// A typo in a resolution should not stall a run: the loader refuses a beam the run could not build.
void check_beam(const DeviceDesc& d, ElementReader& r) {
  const double rays = beam_ray_count(d.value("half_angle_deg"), d.value("resolution_deg"));
  if (rays > static_cast<double>(RangeSensor::kMaxRays))
    r.error(fmt::format("<{}> half_angle_deg {:g} with resolution_deg {:g} needs {} rays per measurement; at most {} "
                        "(use a coarser resolution_deg)",
                        r.name(), d.value("half_angle_deg") / kDegToRad, d.value("resolution_deg") / kDegToRad,
                        rays > 1e6 ? std::string("over 1000000") : fmt::format("{:.0f}", rays), RangeSensor::kMaxRays));
}

std::vector<DeviceParam> beam_params() {
  using T = DeviceParam::Type;
  return {
      {"half_angle_deg", T::Number, 2.0, ranges::kHalfAngle, "deg", "half-width of the beam", {}, kDegToRad},
      {"resolution_deg", T::Number, 1.0, ranges::kResolution, "deg", "rays at most this far apart", {}, kDegToRad},
      {"max_range", T::Number, 1.5, ranges::kMaxRange, "m", "length of the rays; nothing beyond is seen"},
  };
}

}  // namespace

const DeviceKind& gp2d12_kind() {
  static const DeviceKind kind = [] {
    DeviceKind k{"gp2d12", "Sharp GP2D12 analog infrared ranger, 10-80 cm", Mount::PositionYawPitch, 1,
                 {{"adc", WireKind::AdcChannel, true, "the ADC channel its output is on"}},
                 beam_params(),
                 [](const DeviceDesc& d, DeviceHost& h) -> std::unique_ptr<SimDevice> {
                   return std::make_unique<SharpRanger>(d, h, true);
                 },
                 check_beam};
    k.params.push_back({"noise_v", DeviceParam::Type::Number, 0.01, ranges::kNoiseV, "V", "standard deviation of its output"});
    return k;
  }();
  return kind;
}

const DeviceKind& gp2d15_kind() {
  static const DeviceKind kind = [] {
    DeviceKind k{"gp2d15", "Sharp GP2D15 digital infrared ranger, switching at 24 cm", Mount::PositionYawPitch, 1,
                 {{"pin", WireKind::DevicePin, true, "the pin its output drives"}},
                 beam_params(),
                 [](const DeviceDesc& d, DeviceHost& h) -> std::unique_ptr<SimDevice> {
                   return std::make_unique<SharpRanger>(d, h, false);
                 },
                 check_beam};
    k.params.push_back({"switch_distance", DeviceParam::Type::Number, 0.24, ranges::kSwitchDistance, "m",
                        "closer than this turns the output on"});
    k.params.push_back({"hysteresis", DeviceParam::Type::Number, 0.01, ranges::kHysteresis, "m",
                        "farther than switch_distance plus this turns it off"});
    return k;
  }();
  return kind;
}

}  // namespace sear
