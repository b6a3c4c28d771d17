#include "runtime/wiring_report.hpp"

#include <fmt/format.h>

#include <array>

#include "scene/board_pins.hpp"
#include "scene/device_kind.hpp"

namespace sear {
namespace {

class Notes {
 public:
  Notes(const McuBridge& mcu) : mcu_(mcu), usage_(mcu.usage()), kept_(mcu.usage().link.usage_kept == 1) {}

  void devices() {
    const McuDesc& desc = mcu_.desc();
    for (std::size_t i = 0; i < desc.devices.size(); ++i) {
      const DeviceDesc& d = desc.devices[i];
      const std::string who = fmt::format("{} '{}'", d.kind->element, d.name);
      if (d.soft_rx_pin >= 0) {  // on a soft UART's pins
        wired_[static_cast<std::size_t>(d.soft_rx_pin)] = wired_[static_cast<std::size_t>(d.soft_tx_pin)] = true;
        if (kept_ && !usage_.link.pin_read[static_cast<std::size_t>(d.soft_rx_pin)])
          unused(d.name, d.soft_rx_pin, "{}: its TX drives pin {}, which the firmware never read (a soft UART on it, "
                 "digital_read or a pin interrupt)", who, d.soft_rx_pin);
      }
      for (std::size_t w = 0; w < d.wires.size() && w < d.kind->wires.size(); ++w) {
        const int v = d.wires[w];
        if (v < 0) continue;
        const DeviceWire& wire = d.kind->wires[w];
        const auto pin = static_cast<std::size_t>(v);
        switch (wire.kind) {
          case WireKind::McuPin:
            wired_[pin] = true;
            if (wire.use == WireUse::ChipSelect)
              for (const int bus_pin : kMega2560SpiPins) wired_[static_cast<std::size_t>(bus_pin)] = true;
            mcu_pin(d.name, who, wire, v, i);
            break;
          case WireKind::DevicePin:
            wired_[pin] = true;
            if (kept_ && !usage_.link.pin_read[pin])
              unused(d.name, v, "{}: its {} pin {} was never read (digital_read, pulse_in or a pin interrupt)", who,
                     wire.attribute, v);
            break;
          case WireKind::AdcChannel:
            if (kept_ && !(usage_.link.adc_read >> v & 1u))
              unused(d.name, v, "{}: its output on ADC channel {} (pin A{}) was never read (adc_read({}))", who, v, v, v);
            break;
          case WireKind::UartPort:
            wired_[static_cast<std::size_t>(mega2560_uart_rx_pin(v))] = true;
            wired_[static_cast<std::size_t>(mega2560_uart_tx_pin(v))] = true;
            if (!mcu_.device_on_host(i) && !usage_.uart_begun[pin])
              unused(d.name, v, "{}: it is on uart{}, which the firmware never began (uart_begin({}, baud))", who, v, v);
            break;
          case WireKind::I2cAddress:
            for (const int bus_pin : kMega2560I2cPins) wired_[static_cast<std::size_t>(bus_pin)] = true;
            if (kept_ && !addressed(i))
              unused(d.name, v, "{}: at I2C address {} (0x{:02X}) it was never addressed", who, v, v);
            break;
        }
      }
    }
  }

  void actuators() {
    for (const MotorWiring& m : mcu_.desc().motors) {
      const std::string who = fmt::format("motor '{}'", m.motor);
      for (const auto& [name, pin] : {std::pair{"pwm", m.pwm_pin}, {"dir", m.dir_pin}, {"brake", m.brake_pin}}) {
        if (pin < 0) continue;
        wired_[static_cast<std::size_t>(pin)] = true;
        if (std::string(name) != "brake" && !driven(pin))
          unused(m.motor, pin, "{}: its {} pin {} was never set as an OUTPUT nor given PWM: the firmware never drove it",
                 who, name, pin);
      }
    }
    for (const ServoWiring& s : mcu_.desc().servos) {
      if (s.pin < 0) continue;
      wired_[static_cast<std::size_t>(s.pin)] = true;
      // Pulses count from servo_write_us, a PWM timer, or HIGHs of 400..2600 us on the pin itself.
      const auto p = static_cast<std::size_t>(s.pin);
      if (usage_.waveform[p]) continue;
      if (usage_.levels[p] & 2)
        unused(s.servo, s.pin,
               "servo '{}': its pin {} never got servo pulses: the firmware drove it HIGH, but never for 400..2600 us "
               "at a time, 3 ms or more apart",
               s.servo, s.pin);
      else
        unused(s.servo, s.pin, "servo '{}': its pin {} never got servo pulses: the firmware never drove it", s.servo, s.pin);
    }
  }

  void pins() {
    for (std::size_t p = 0; p < SEAR_LINK_PINS; ++p) {
      const int pin = static_cast<int>(p);
      const std::uint8_t written = usage_.link.input_write[p];
      // A write before the pin became an output presets its level: no note then.
      if (kept_ && (written == 1 || written == 2) && !driven(pin))
        add(WiringNote::Kind::InputWrite, "", pin,
            "a digital_write of {} to pin {} at {:.9f} s, a pin never set as an OUTPUT, only turned its pull-up {} "
            "(as on the chip); pin_mode({}, OUTPUT) first makes it drive",
            written == 2 ? "HIGH" : "LOW", pin, static_cast<double>(usage_.link.input_write_ns[p]) * 1e-9,
            written == 2 ? "on" : "off", pin);
    }
    for (std::size_t p = 0; p < SEAR_LINK_PINS; ++p) {
      const int pin = static_cast<int>(p);
      if (driven(pin) && !wired_[p])
        add(WiringNote::Kind::UnwiredPin, "", pin,
            "the firmware drove pin {} as an output, and nothing in the project is wired to it (fine for an LED; "
            "if a device should be there, check which pin it is wired to)",
            pin);
    }
  }

  std::vector<WiringNote> take() { return std::move(notes_); }

 private:
  bool driven(int pin) const {
    const auto p = static_cast<std::size_t>(pin);
    return usage_.made_output[p] || usage_.waveform[p];
  }

  bool addressed(std::size_t device) const {
    const auto& inputs = mcu_.input_devices();
    for (std::size_t in = 0; in < inputs.size() && in < 32; ++in)
      if (inputs[in] == device && (usage_.link.inputs_addressed >> in & 1u)) return true;
    return false;
  }

  void mcu_pin(const std::string& name, const std::string& who, const DeviceWire& wire, int v, std::size_t device) {
    const auto p = static_cast<std::size_t>(v);
    if (!driven(v)) {
      unused(name, v, "{}: its {} pin {} was never set as an OUTPUT: the firmware never drove it", who, wire.attribute, v);
    } else if (wire.use == WireUse::Pulses && usage_.levels[p] != 3) {
      unused(name, v, "{}: its {} pin {} was an OUTPUT held {} the whole run: the firmware never pulsed it", who,
             wire.attribute, v, usage_.levels[p] == 2 ? "HIGH" : "LOW");
    } else if (wire.use == WireUse::ChipSelect && kept_ && !addressed(device)) {
      unused(name, v, "{}: its {} pin {} never selected it for an SPI transfer (spi_transfer with the pin LOW)", who,
             wire.attribute, v);
    }
  }

  template <class... Args>
  void unused(const std::string& device, int pin, fmt::format_string<Args...> format, Args&&... args) {
    add(WiringNote::Kind::Unused, device, pin, format, std::forward<Args>(args)...);
  }

  template <class... Args>
  void add(WiringNote::Kind kind, const std::string& device, int pin, fmt::format_string<Args...> format,
           Args&&... args) {
    notes_.push_back({kind, mcu_.id(), device, pin,
                      fmt::format("mcu {}: {}", mcu_.id(), fmt::format(format, std::forward<Args>(args)...))});
  }

  const McuBridge& mcu_;
  const McuUsage& usage_;
  const bool kept_;
  std::array<bool, SEAR_LINK_PINS> wired_{};
  std::vector<WiringNote> notes_;
};

}  // namespace

const char* kind_name(WiringNote::Kind kind) {
  switch (kind) {
    case WiringNote::Kind::Unused: return "unused wiring";
    case WiringNote::Kind::InputWrite: return "write to an input";
    case WiringNote::Kind::UnwiredPin: return "unwired output";
  }
  return "note";
}

std::vector<WiringNote> wiring_notes(const McuBridge& mcu) {
  Notes notes(mcu);
  notes.devices();
  notes.actuators();
  notes.pins();
  return notes.take();
}

}  // namespace sear
