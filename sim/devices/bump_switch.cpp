// A bump switch: a lever across the robot that closes a contact to ground while anything is within
// its reach, felt along its whole width by parallel rays; read every quantum.
#include <cmath>

#include "devices/device_kinds.hpp"
#include "devices/sim_device.hpp"
#include "scene/value_ranges.hpp"
#include "sensors/range_sensor.hpp"

namespace sear {
namespace {

// Parallel rays at most 2 cm apart, each its reach long.
std::vector<RangeSensor> lever_rays(const DeviceDesc& d) {
  const double width = d.value("width");
  const int n = std::max(1, static_cast<int>(std::ceil(width / 0.02))) + 1;
  const Eigen::Vector3d across(-std::sin(d.yaw_rad), std::cos(d.yaw_rad), 0);
  std::vector<RangeSensor> rays;
  for (int i = 0; i < n; ++i) {
    RangeBeam beam;
    beam.position_m = d.position_m + across * (width * (static_cast<double>(i) / (n - 1) - 0.5));
    beam.yaw_rad = d.yaw_rad;
    beam.max_range_m = d.value("reach");
    rays.emplace_back(beam);
  }
  return rays;
}

class BumpSwitch : public SimDevice {
 public:
  BumpSwitch(const DeviceDesc& d, DeviceHost& host) : lever_(lever_rays(d)) {
    sear_link_input in = blank_input(SEAR_INPUT_SWITCH);
    in.pins[0] = static_cast<std::uint32_t>(d.wire("pin"));
    input_ = host.add_input(in);
  }
  void sample(const SenseContext& c, SampleSink& sink) override {
    const bool closed = lever_.any_hit(c.physics, c.chassis, c.self_entity);  // one search of the world per lever
    sink.add(c.t0_ns, 0, input_, {closed ? 1.0 : 0.0});
  }

 private:
  RangeSensorSet lever_;
  std::uint32_t input_ = 0;
};

}  // namespace

const DeviceKind& bump_kind() {
  static const DeviceKind kind{
      "bump", "a bump switch to ground: a lever that closes while anything is within its reach",
      Mount::PositionYaw, 1,
      {{"pin", WireKind::DevicePin, true, "the pin its contact pulls to ground"}},
      {{"width", DeviceParam::Type::Number, 0.1, ranges::kBumpWidth, "m", "the lever's width across"},
       {"reach", DeviceParam::Type::Number, 0.01, ranges::kBumpReach, "m", "how far ahead of its base it closes"}},
      [](const DeviceDesc& d, DeviceHost& h) -> std::unique_ptr<SimDevice> { return std::make_unique<BumpSwitch>(d, h); }};
  return kind;
}

}  // namespace sear
