// MaxBotix LV-MaxSonar-EZ1: one reading every 49 ms from a wide cone, given at once on all the
// outputs that are wired: analog and pulse width (played out in the firmware's process) and the
// serial "R###\r" at 9600 baud, which this device sends from the simulator's process.
#include <cmath>

#include "devices/beams.hpp"
#include "devices/device_kinds.hpp"
#include "devices/sim_device.hpp"
#include "devices/uart_device.hpp"
#include "scene/value_ranges.hpp"

extern "C" {
#include "devices/maxbotix_lv_ez.h"
}

namespace sear {
namespace {

class Maxbotix : public SimDevice, public UartDevice {
 public:
  Maxbotix(const DeviceDesc& d, DeviceHost& host)
      : sensor_(beam_of(d)),
        seed_(host.seed(0)),
        noise_sd_m_(d.value("noise")),
        serial_wired_(d.wire("serial_uart") >= 0 || d.soft_rx_pin >= 0),
        inverted_(d.value("inverter") == 0) {
    const int adc = d.wire("adc"), pw = d.wire("pw");
    if (adc >= 0 || pw >= 0) {
      sear_link_input in = blank_input(SEAR_INPUT_MAXBOTIX);
      if (adc >= 0) in.pins[0] = static_cast<std::uint32_t>(adc);
      if (pw >= 0) in.pins[1] = static_cast<std::uint32_t>(pw);
      input_ = static_cast<int>(host.add_input(in));
    }
    maxbotix_schedule_init(&schedule_);
    maxbotix_lv_ez_serial_init(&serial_, seed_, noise_sd_m_);
  }

  // One measurement per ranging cycle, at its start; the serial half measures the same cycle with
  // the same distance, seed and number, so all three outputs give the same reading.
  void sample(const SenseContext& c, SampleSink& sink) override {
    std::uint64_t k = 0;
    for (std::int64_t t = maxbotix_schedule_next_ns(&schedule_, &k); t < c.t1_ns;
         t = maxbotix_schedule_next_ns(&schedule_, &k)) {
      const RangeReading r = sensor_.measure(c.physics, c.chassis, c.self_entity);
      const double distance = r.hit ? r.distance_m : INFINITY;
      if (input_ >= 0)
        sink.add(std::max(t, c.t0_ns), k, static_cast<std::uint32_t>(input_),
                 {static_cast<double>(maxbotix_reading_inches(distance, seed_, k, noise_sd_m_))});
      maxbotix_lv_ez_serial_set_distance(&serial_, distance, t);
      maxbotix_schedule_take(&schedule_);
    }
  }

  // The RX pin is pulled up inside the part: let go, it ranges.
  void pin_written(int pin, int level, std::int64_t t_ns) override {
    (void)pin;
    const int rx = level < 0 ? 1 : level;
    maxbotix_schedule_set_rx(&schedule_, rx, t_ns);
    maxbotix_lv_ez_serial_set_rx_level(&serial_, rx, t_ns);
  }

  UartDevice* uart() override { return serial_wired_ ? this : nullptr; }
  void receive(const serial_byte&) override {}  // the part has no serial input
  std::size_t transmit(std::int64_t now_ns, std::int64_t until_ns, serial_byte* out, std::size_t cap) override {
    return maxbotix_lv_ez_serial_transmit(&serial_, now_ns, until_ns, out, cap);
  }
  std::uint32_t baud() const override { return MAXBOTIX_BAUD; }
  bool inverted() const override { return inverted_; }

 private:
  RangeSensor sensor_;
  std::uint64_t seed_;
  double noise_sd_m_;
  bool serial_wired_;
  bool inverted_;  // RS-232 polarity reaches the MCU unless the wiring has an inverter
  int input_ = -1;
  maxbotix_schedule schedule_{};
  maxbotix_lv_ez_serial serial_{};
};

void check_outputs(const DeviceDesc& d, ElementReader& r) {
  check_beam(d, r);
  if (d.wire("adc") < 0 && d.wire("pw") < 0 && d.wire("serial_uart") < 0 && d.soft_rx_pin < 0)
    r.error("<maxbotix_lv_ez> wires none of its outputs: give 'adc', 'pw' or 'serial_uart'");
}

}  // namespace

const DeviceKind& maxbotix_lv_ez_kind() {
  static const DeviceKind kind = [] {
    DeviceKind k{"maxbotix_lv_ez",
                 "MaxBotix LV-MaxSonar-EZ1 sonar, 6-254 in, every 49 ms: analog Vcc/512 per inch, pulse width "
                 "147 us per inch, serial R###<CR> at 9600 baud (RS-232 polarity)",
                 Mount::PositionYawPitch, 1,
                 {{"adc", WireKind::AdcChannel, false, "the ADC channel of its AN output"},
                  {"pw", WireKind::DevicePin, false, "the pin of its PW output"},
                  {"serial_uart", WireKind::UartPort, false, "the UART whose RX its TX output drives"},
                  {"rx", WireKind::McuPin, false, "the pin driving its RX: held low, it stops ranging"}},
                 sonar_params(15.0, 2.0, 6.5, 45.0),
                 [](const DeviceDesc& d, DeviceHost& h) -> std::unique_ptr<SimDevice> {
                   return std::make_unique<Maxbotix>(d, h);
                 },
                 check_outputs};
    k.params.push_back({"noise", DeviceParam::Type::Number, MAXBOTIX_NOISE_SD_M, ranges::kRangeNoise, "m",
                        "standard deviation of a reading before it is cut to whole inches"});
    k.params.push_back({"inverter", DeviceParam::Type::Choice, 0, {}, "",
                        "true when the serial output passes an inverter (as an AVR's UART needs)",
                        {"false", "true"}});
    return k;
  }();
  return kind;
}

}  // namespace sear
