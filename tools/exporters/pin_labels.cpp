#include "exporters/pin_labels.hpp"

#include <cstring>

#include "exporters/pin_waveform.hpp"
#include "lockstep_link.h"
#include "scene/description.hpp"
#include "scene/device_kind.hpp"

namespace sear {
namespace {

// A name may hold any printable text (spaces included), which would end a VCD name early.
std::string plain(const std::string& name) {
  std::string safe;
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '-' || c == '.';
    safe += ok ? c : '_';
  }
  return safe;
}

// ADC channel n is pin A<n>, the board's pins after the digital ones (54 + n on the Mega).
constexpr int kFirstAdcPin = SEAR_LINK_PINS - SEAR_LINK_ADC_CHANNELS;

}  // namespace

std::vector<std::string> pin_labels(const McuDesc& mcu) {
  std::vector<std::string> labels(SEAR_LINK_PINS);
  const auto add = [&](int pin, const std::string& label) {
    if (pin < 0 || pin >= SEAR_LINK_PINS) return;
    labels[pin] += (labels[pin].empty() ? "" : "+") + label;
  };
  // A UART is named from the far end's side, as it is wired: the device's RX on the MCU's TX.
  const auto add_uart = [&](int port, const std::string& far_end, bool rx_only) {
    if (port < 0 || port >= SEAR_LINK_UARTS) return;
    if (!rx_only) add(PinWaveform::uart_tx_pin(port), far_end + ".rx");
    add(PinWaveform::uart_rx_pin(port), far_end + ".tx");
  };
  if (mcu.console_uart >= 0) add_uart(mcu.console_uart, "console", false);
  for (const auto& uart : mcu.uarts)
    if (uart.loopback) {
      add(PinWaveform::uart_tx_pin(uart.port), "loopback");
      add(PinWaveform::uart_rx_pin(uart.port), "loopback");
    }
  for (const auto& device : mcu.devices) {
    const std::string name = plain(device.name);
    if (device.soft_rx_pin >= 0) {  // on a soft UART's pins, named from its side as a port's are
      add(device.soft_rx_pin, name + ".tx");
      add(device.soft_tx_pin, name + ".rx");
    }
    for (std::size_t w = 0; w < device.kind->wires.size() && w < device.wires.size(); ++w) {
      const DeviceWire& wire = device.kind->wires[w];
      const int at = device.wires[w];
      if (at < 0) continue;
      // A one-pin part's "pin" is the part itself: a bump switch reads as "bumper".
      const std::string label = std::strcmp(wire.attribute, "pin") == 0 ? name : name + "." + wire.attribute;
      switch (wire.kind) {
        case WireKind::DevicePin:
        case WireKind::McuPin: add(at, label); break;
        case WireKind::AdcChannel: add(kFirstAdcPin + at, label); break;
        // Its TX only when it talks one way (a MaxBotix's serial output, wired to RX alone).
        case WireKind::UartPort: add_uart(at, name, std::strcmp(wire.attribute, "uart") != 0); break;
        case WireKind::I2cAddress: break;  // an address, not a pin
      }
    }
  }
  for (const auto& m : mcu.motors) {
    add(m.pwm_pin, plain(m.motor) + ".pwm");
    add(m.dir_pin, plain(m.motor) + ".dir");
    add(m.brake_pin, plain(m.motor) + ".brake");
  }
  for (const auto& s : mcu.servos) add(s.pin, plain(s.servo) + ".signal");
  return labels;
}

}  // namespace sear
