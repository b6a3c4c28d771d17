// A quadrature encoder on a wheel's shaft: the wheel's spin relative to the chassis, integrated
// from the physics each quantum and given with its rate, so that the model in the firmware's
// process puts every edge at the time the shaft crosses it. A wheel that slips turns the encoder
// all the same: odometry errs as on hardware.
#include <algorithm>
#include <cmath>

#include "devices/device_kinds.hpp"
#include "devices/sim_device.hpp"

namespace sear {
namespace {

// Catalogue encoders on hobby gearmotors give 12 to a few thousand cycles per revolution of the
// wheel; 1e5 keeps an edge's spacing above a nanosecond at any wheel speed ODE allows.
const Range kCyclesPerRev = Range::between(1, 100000, "1..100000");

class Encoder : public SimDevice {
 public:
  Encoder(const DeviceDesc& d, DeviceHost& host) : wheel_name_(d.text("wheel")) {
    sear_link_input in = blank_input(SEAR_INPUT_ENCODER);
    in.pins[0] = static_cast<std::uint32_t>(d.wire("a"));
    in.pins[1] = static_cast<std::uint32_t>(d.wire("b"));
    in.param[0] = d.value("cycles_per_rev");
    input_ = host.add_input(in);
  }

  void sample(const SenseContext& c, SampleSink& sink) override {
    if (wheel_ < 0) {
      const auto& wheels = c.vehicle.desc().wheels;
      const auto it = std::find_if(wheels.begin(), wheels.end(), [&](const WheelDesc& w) { return w.name == wheel_name_; });
      wheel_ = static_cast<int>(it - wheels.begin());  // the loader checked that it exists
    }
    // The angle the rate held over the last quantum brought it to: the firmware's edges and this
    // integral are the same piecewise-linear motion, so no count is ever lost or made up.
    angle_rad_ += rate_radps_ * static_cast<double>(c.t0_ns - t_ns_) * 1e-9;
    t_ns_ = c.t0_ns;
    rate_radps_ = c.vehicle.wheel_speed(static_cast<std::size_t>(wheel_));
    sink.add(c.t0_ns, 0, input_, {angle_rad_, rate_radps_});
  }

 private:
  std::string wheel_name_;
  int wheel_ = -1;
  std::uint32_t input_ = 0;
  double angle_rad_ = 0;
  double rate_radps_ = 0;
  std::int64_t t_ns_ = 0;
};

}  // namespace

const DeviceKind& quadrature_encoder_kind() {
  static const DeviceKind kind{
      "quadrature_encoder", "an incremental encoder on a wheel: channels A and B in quadrature, A leading forward",
      Mount::None, 1,
      {{"a", WireKind::DevicePin, true, "the pin of channel A"}, {"b", WireKind::DevicePin, true, "the pin of channel B"}},
      {{"wheel", DeviceParam::Type::Wheel, 0, {}, "", "the wheel whose shaft it reads"},
       {"cycles_per_rev", DeviceParam::Type::Whole, 90, kCyclesPerRev, "",
        "full cycles of each channel per wheel revolution (a decoder counting every edge gets 4 times this)"}},
      [](const DeviceDesc& d, DeviceHost& h) -> std::unique_ptr<SimDevice> { return std::make_unique<Encoder>(d, h); }};
  return kind;
}

}  // namespace sear
