// Sharp GP2D12 (analog) and GP2D15 (digital) infrared rangers: a narrow beam of rays measured
// every 38.3 ms; the transfer curve and the switch run in the firmware's process.
#include <cmath>

#include "devices/beams.hpp"
#include "devices/device_kinds.hpp"
#include "devices/sim_device.hpp"
#include "scene/value_ranges.hpp"

extern "C" {
#include "devices/sharp_gp2d12.h"
}

namespace sear {
namespace {

class SharpRanger : public SimDevice {
 public:
  SharpRanger(const DeviceDesc& d, DeviceHost& host, bool analog) : sensor_(beam_of(d)) {
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
    for_each_tick(kPeriod, c, [&](std::int64_t k) {
      const RangeReading r = sensor_.measure(c.physics, c.chassis, c.self_entity);
      sink.add(k * kPeriod, static_cast<std::uint64_t>(k), input_, {r.hit ? r.distance_m : INFINITY});
    });
  }

 private:
  static constexpr std::int64_t kPeriod = GP2D12_PERIOD_NS;  // both parts measure on the same cycle
  RangeSensor sensor_;
  std::uint32_t input_ = 0;
};

}  // namespace

const DeviceKind& gp2d12_kind() {
  static const DeviceKind kind = [] {
    DeviceKind k{"gp2d12", "Sharp GP2D12 analog infrared ranger, 10-80 cm", Mount::PositionYawPitch, 1,
                 {{"adc", WireKind::AdcChannel, true, "the ADC channel its output is on"}},
                 beam_params(2.0, 1.0, 1.5),
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
                 beam_params(2.0, 1.0, 1.5),
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
