// The pulse width each servo reads on its wire: from the levels the firmware drives on the pin (a
// servo library toggling it from a timer interrupt, or digital_write and a delay), or from the
// widths the HAL's servo_write_us and the AVR engine's PWM timers announce without edges.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "lockstep_link.h"

namespace sear {

// What a hobby servo takes as a pulse. 400..2600 us is the width servo_write_us accepts: the
// widest servos' travel (500..2500 us for 180 degrees) with a margin, where a receiver's
// channel never goes; a longer HIGH is a level, not a pulse. A frame (rising edge to rising
// edge) of 3 ms is the fastest refresh digital servos are rated for (333 Hz): PWM at 490 or
// 976 Hz is not servo pulses. With no pulse for 50 ms (two and a half 20 ms frames) the servo's
// driver lets go, as after servo_write_us(pin, 0).
struct ServoPulseBounds {
  static constexpr std::int64_t kMinPulseNs = 400'000;
  static constexpr std::int64_t kMaxPulseNs = 2'600'000;
  static constexpr std::int64_t kMinFrameNs = 3'000'000;
  static constexpr std::int64_t kTimeoutNs = 50'000'000;
};

class ServoWires {
 public:
  // `pins`: the MCU's pins wired to a servo; every other pin is ignored.
  explicit ServoWires(const std::vector<int>& pins);

  // The firmware drove `pin` to `level` at time_ns. True when that ended a pulse the servo takes;
  // it reaches the servo from that falling edge on.
  bool level(std::size_t pin, bool level, std::int64_t time_ns);
  // A width announced without edges (SEAR_EVENT_SERVO; 0: pulses stop), from time_ns on. The
  // later of an announced width and a pulse read on the wire is what the servo follows.
  void announced(std::size_t pin, int pulse_us);
  // The width the servo on `pin` follows at now_ns, in microseconds; 0 for none.
  double pulse_us(std::size_t pin, std::int64_t now_ns) const;

 private:
  struct Wire {
    bool servo = false;  // a servo is wired to this pin
    bool high = false;
    bool any_rise = false;
    bool rose = false;  // rise_ns holds a rising edge not yet ended by a falling one
    std::int64_t rise_ns = 0;
    bool framed = false;  // last_rise_ns holds the rising edge of the pulse before
    std::int64_t last_rise_ns = 0;
    double pulse_us = 0;
    bool from_wire = false;        // pulse_us was read on the wire, so it lapses without pulses
    std::int64_t pulse_rise_ns = 0;  // the rising edge of that pulse
  };
  std::array<Wire, SEAR_LINK_PINS> wires_{};
};

}  // namespace sear
