// Honeywell HMC5883L and QST QMC5883L magnetometers (both sold as "HMC5883L" boards): the Earth's
// field from the world's <magnetic> figures, or the World Magnetic Model at the GPS origin, turned
// into the sensor's axes as the robot tilts and turns; their registers run in the firmware's process.
#include <fmt/format.h>

#include <cmath>

#include "devices/device_kinds.hpp"
#include "devices/mounting.hpp"
#include "devices/sim_device.hpp"
#include "sensors/magnetic_field.hpp"

namespace sear {
namespace {

// The world's figures where it gives them, the model's elsewhere.
GeomagneticElements field_of(const WorldDesc& w) {
  GeomagneticElements e = wmm2025_elements(w.gps_origin, w.magnetic_year);
  if (std::isfinite(w.magnetic_declination_rad)) e.declination_rad = w.magnetic_declination_rad;
  if (std::isfinite(w.magnetic_inclination_rad)) e.inclination_rad = w.magnetic_inclination_rad;
  if (std::isfinite(w.magnetic_intensity_T)) e.intensity_T = w.magnetic_intensity_T;
  return e;
}

class Compass : public SimDevice {
 public:
  Compass(const DeviceDesc& d, DeviceHost& host, sear_input_kind kind)
      : field_enu_T_(field_enu_T(field_of(host.world()))), body_from_sensor_(body_from_sensor(d)) {
    sear_link_input in = blank_input(kind);
    in.pins[0] = static_cast<std::uint32_t>(d.wire("address"));
    for (const DeviceWire& w : d.kind->wires)
      if (std::string(w.attribute) == "drdy" && d.wire("drdy") >= 0) in.pins[1] = static_cast<std::uint32_t>(d.wire("drdy"));
    input_ = host.add_input(in);
  }

  void sample(const SenseContext& c, SampleSink& sink) override {
    const dReal* r = dBodyGetRotation(c.chassis);  // row-major 3x4
    Eigen::Matrix3d world_from_body;
    world_from_body << r[0], r[1], r[2], r[4], r[5], r[6], r[8], r[9], r[10];
    const Eigen::Vector3d b = field_in_sensor_T(field_enu_T_, world_from_body * body_from_sensor_);
    sink.add(c.t0_ns, 0, input_, {b.x(), b.y(), b.z()});
  }

 private:
  Eigen::Vector3d field_enu_T_;
  Eigen::Matrix3d body_from_sensor_;
  std::uint32_t input_ = 0;
};

// Each part answers at one address only.
template <int Address>
void check_fixed_address(const DeviceDesc& d, ElementReader& r) {
  if (d.wire("address") != Address)
    r.error(fmt::format("<{}> answers only at I2C address {} (0x{:02X})", d.kind->element, Address, Address));
}

}  // namespace

const DeviceKind& hmc5883l_kind() {
  static const DeviceKind kind{
      "hmc5883l", "Honeywell HMC5883L 3-axis magnetometer on I2C (0x1E; identification 'H43')", Mount::Full, 1,
      {{"address", WireKind::I2cAddress, false, "its I2C address, fixed at 30 (0x1E)", 0x1E},
       {"drdy", WireKind::DevicePin, false, "the pin its DRDY output drives"}},
      {},
      [](const DeviceDesc& d, DeviceHost& h) -> std::unique_ptr<SimDevice> {
        return std::make_unique<Compass>(d, h, SEAR_INPUT_HMC5883L);
      },
      check_fixed_address<0x1E>};
  return kind;
}

const DeviceKind& qmc5883l_kind() {
  static const DeviceKind kind{
      "qmc5883l", "QST QMC5883L 3-axis magnetometer on I2C (0x0D), fitted to most cheap 'HMC5883L' boards",
      Mount::Full, 1,
      {{"address", WireKind::I2cAddress, false, "its I2C address, fixed at 13 (0x0D)", 0x0D}},
      {},
      [](const DeviceDesc& d, DeviceHost& h) -> std::unique_ptr<SimDevice> {
        return std::make_unique<Compass>(d, h, SEAR_INPUT_QMC5883L);
      },
      check_fixed_address<0x0D>};
  return kind;
}

}  // namespace sear
