// InvenSense MPU-6000 (SPI) and MPU-6050 (I2C): the specific force and angular rate at the mount,
// lever arm included, sampled once a quantum; the register file, its sampling, filter and errors
// run in the firmware's process (hal/devices/mpu6000).
#include <cmath>

#include "devices/device_kinds.hpp"
#include "devices/mounting.hpp"
#include "devices/sim_device.hpp"
#include "sensors/imu_truth.hpp"

namespace sear {
namespace {


ImuMount mount_of(const DeviceDesc& d) {
  ImuMount m;
  m.position_m = d.position_m;
  m.body_from_sensor = body_from_sensor(d);
  return m;
}

class Mpu : public SimDevice {
 public:
  Mpu(const DeviceDesc& d, DeviceHost& host, bool spi) : truth_(mount_of(d), host.world().gravity) {
    sear_link_input in = blank_input(spi ? SEAR_INPUT_MPU6000 : SEAR_INPUT_MPU6050);
    in.pins[0] = static_cast<std::uint32_t>(spi ? d.wire("cs") : d.wire("address"));
    if (d.wire("int") >= 0) in.pins[1] = static_cast<std::uint32_t>(d.wire("int"));
    // Negative: the datasheet's figure, which the model in the firmware's process knows.
    in.param[0] = d.value("gyro_noise");
    in.param[1] = d.value("gyro_bias");
    in.param[2] = d.value("accel_noise");
    in.param[3] = d.value("self_test_error");
    input_ = host.add_input(in);
  }

  // Once a quantum, after the step that ended at t0: ImuTruth differentiates the body's velocity
  // over that step.
  void sample(const SenseContext& c, SampleSink& sink) override {
    const ImuSample s = truth_.update(c.chassis, static_cast<double>(c.t1_ns - c.t0_ns) * 1e-9);
    sink.add(c.t0_ns, 0, input_,
             {s.specific_force_mps2.x(), s.specific_force_mps2.y(), s.specific_force_mps2.z(), s.rate_radps.x(),
              s.rate_radps.y(), s.rate_radps.z()});
  }

 private:
  ImuTruth truth_;
  std::uint32_t input_ = 0;
};

// Datasheet figures are the defaults (PS-MPU-6000A table 6.1/6.2); -1 keeps them.
std::vector<DeviceParam> imu_params() {
  using T = DeviceParam::Type;
  return {{"gyro_noise", T::Number, -1, {-1, 1, false, "0..1 deg/s/sqrt(Hz), or -1 for the datasheet's 0.005"}, "deg/s/sqrt(Hz)",
           "gyro rate noise density", {}, kDegToRad},
          {"gyro_bias", T::Number, -1, {-1, 100, false, "0..100 deg/s, or -1 for the datasheet's"}, "deg/s",
           "standard deviation of each axis' zero-rate offset at power-up", {}, kDegToRad},
          {"accel_noise", T::Number, -1, {-1, 100000, false, "0..100000 ug/sqrt(Hz), or -1 for the datasheet's 400"},
           "ug/sqrt(Hz)", "accelerometer noise density", {}, 9.80665e-6},
          {"self_test_error", T::Number, 0, {-1, 1, false, "-1..1"}, "",
           "how far the self-test response is from its factory trim, as a fraction: 0 for a healthy part; "
           "beyond -0.14..0.14 it fails InvenSense's self-test (PS 6.1/6.2)",
           {}, 1.0}};
}

}  // namespace

const DeviceKind& mpu6000_kind() {
  static const DeviceKind kind{
      "mpu6000", "InvenSense MPU-6000 6-axis IMU on SPI (mode 0 or 3; writes at <= 1 MHz, reads at <= 20 MHz)",
      Mount::Full, 1,
      {{"cs", WireKind::McuPin, true, "its chip-select pin, active low", -1, WireUse::ChipSelect},
       {"int", WireKind::DevicePin, false, "the pin its INT (data ready) output drives"}},
      imu_params(),
      [](const DeviceDesc& d, DeviceHost& h) -> std::unique_ptr<SimDevice> { return std::make_unique<Mpu>(d, h, true); }};
  return kind;
}

// AD0 picks one of two addresses; the part answers no other.
static void check_address(const DeviceDesc& d, ElementReader& r) {
  if (d.wire("address") != 0x68 && d.wire("address") != 0x69)
    r.error("<mpu6050> 'address' must be 104 (0x68) or 105 (0x69, AD0 high)");
}

const DeviceKind& mpu6050_kind() {
  static const DeviceKind kind{
      "mpu6050", "InvenSense MPU-6050 6-axis IMU on I2C (0x68, or 0x69 with AD0 high)", Mount::Full, 1,
      {{"address", WireKind::I2cAddress, false, "its I2C address, 104 (0x68) or 105 (0x69)", 0x68},
       {"int", WireKind::DevicePin, false, "the pin its INT (data ready) output drives"}},
      imu_params(),
      [](const DeviceDesc& d, DeviceHost& h) -> std::unique_ptr<SimDevice> { return std::make_unique<Mpu>(d, h, false); },
      check_address};
  return kind;
}

}  // namespace sear
