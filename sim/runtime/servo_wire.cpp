// Decodes the servo pulses on the pins wired to servos (see servo_wire.hpp).
#include "runtime/servo_wire.hpp"

namespace sear {

ServoWires::ServoWires(const std::vector<int>& pins) {
  for (int p : pins)
    if (p >= 0 && p < SEAR_LINK_PINS) wires_[static_cast<std::size_t>(p)].servo = true;
}

bool ServoWires::level(std::size_t pin, bool level, std::int64_t time_ns) {
  Wire& w = wires_[pin];
  if (!w.servo || level == w.high) return false;
  w.high = level;
  if (level) {
    w.framed = w.any_rise;
    w.last_rise_ns = w.rise_ns;
    w.rise_ns = time_ns;
    w.any_rise = true;
    w.rose = true;
    return false;
  }
  if (!w.rose) return false;
  w.rose = false;
  const std::int64_t width = time_ns - w.rise_ns;
  if (width < ServoPulseBounds::kMinPulseNs || width > ServoPulseBounds::kMaxPulseNs) return false;
  // Pulses closer than a servo's fastest frame are PWM, not servo pulses; the wire's first pulse
  // and one after a pause have no frame to fail.
  const std::int64_t frame = w.rise_ns - w.last_rise_ns;
  if (w.framed && frame < ServoPulseBounds::kMinFrameNs) return false;
  w.pulse_us = static_cast<double>(width) * 1e-3;
  w.from_wire = true;
  w.pulse_rise_ns = w.rise_ns;
  return true;
}

void ServoWires::announced(std::size_t pin, int pulse_us) {
  Wire& w = wires_[pin];
  w.pulse_us = pulse_us;
  w.from_wire = false;
}

double ServoWires::pulse_us(std::size_t pin, std::int64_t now_ns) const {
  if (pin >= wires_.size()) return 0;
  const Wire& w = wires_[pin];
  if (w.from_wire && now_ns - w.pulse_rise_ns > ServoPulseBounds::kTimeoutNs) return 0;
  return w.pulse_us;
}

}  // namespace sear
