// HC-SR04 ultrasonic ranger: a wide cone measured for its model in the firmware's process, which
// answers the firmware's TRIG pulses with ECHO pulses at their exact times.
#include <cmath>

#include "devices/beams.hpp"
#include "devices/device_kinds.hpp"
#include "devices/sim_device.hpp"

namespace sear {
namespace {

// The firmware may trigger at any instant, and the echo starts well within a quantum of it, so
// the truth is kept fresh rather than measured on demand: every 10 ms, in which a robot at
// 0.3 m/s moves 3 mm, the part's own resolution.
constexpr std::int64_t kTruthPeriodNs = 10'000'000;

class Hcsr04 : public SimDevice {
 public:
  Hcsr04(const DeviceDesc& d, DeviceHost& host) : sensor_(beam_of(d)) {
    sear_link_input in = blank_input(SEAR_INPUT_HCSR04);
    in.pins[0] = static_cast<std::uint32_t>(d.wire("trig"));
    in.pins[1] = static_cast<std::uint32_t>(d.wire("echo"));
    input_ = host.add_input(in);
  }
  void sample(const SenseContext& c, SampleSink& sink) override {
    for_each_tick(kTruthPeriodNs, c, [&](std::int64_t k) {
      const RangeReading r = sensor_.measure(c.physics, c.chassis, c.self_entity);
      sink.add(k * kTruthPeriodNs, static_cast<std::uint64_t>(k), input_, {r.hit ? r.distance_m : INFINITY});
    });
  }

 private:
  RangeSensor sensor_;
  std::uint32_t input_ = 0;
};

}  // namespace

const DeviceKind& hcsr04_kind() {
  static const DeviceKind kind = [] {
    DeviceKind k{"hcsr04", "HC-SR04 ultrasonic ranger, 2 cm to 4 m: TRIG in, ECHO pulse out (58 us per cm)",
                 Mount::PositionYawPitch, 1,
                 {{"trig", WireKind::McuPin, true, "the pin the firmware pulses to start a measurement", -1, WireUse::Pulses},
                  {"echo", WireKind::DevicePin, true, "the pin the echo pulse comes back on"}},
                 sonar_params(15.0, 2.0, 4.5, 45.0),
                 [](const DeviceDesc& d, DeviceHost& h) -> std::unique_ptr<SimDevice> {
                   return std::make_unique<Hcsr04>(d, h);
                 },
                 check_beam};
    return k;
  }();
  return kind;
}

}  // namespace sear
