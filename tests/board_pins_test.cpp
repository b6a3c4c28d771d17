// The loader's tables of the Mega 2560's PWM and pin-change pins (sim/scene/board_pins.hpp) are the
// ones the firmware's side refuses pwm_write() and soft_uart_begin() by (hal/runtime/board.c), pin
// for pin: a project the loader passes must not stop its firmware, and one it refuses must be one
// that would.
#include <gtest/gtest.h>

#include "scene/board_pins.hpp"

extern "C" {
#include "board.h"
}

namespace sear {
namespace {

TEST(BoardPins, LoaderAndFirmwareAgreeOnEveryPwmPin) {
  int pwm_pins = 0;
  for (int pin = 0; pin < 70; ++pin) {  // SEAR_LINK_PINS: the board's 70 pins
    EXPECT_EQ(mega2560_has_pwm(pin), board_has_pwm(static_cast<std::uint8_t>(pin)) != 0) << "pin " << pin;
    pwm_pins += mega2560_has_pwm(pin) ? 1 : 0;
  }
  // The Mega 2560 has 15 PWM outputs (Arduino's board page): 12 on 2..13 and 3 on 44..46.
  EXPECT_EQ(pwm_pins, 15);
}

TEST(BoardPins, LoaderAndFirmwareAgreeOnEveryPinChangePin) {
  int pin_change_pins = 0;
  for (int pin = 0; pin < 70; ++pin) {
    EXPECT_EQ(mega2560_has_pin_change(pin), board_has_pin_change(static_cast<std::uint8_t>(pin)) != 0) << "pin " << pin;
    pin_change_pins += mega2560_has_pin_change(pin) ? 1 : 0;
  }
  // PCINT0..7 (port B, 4 of them on 50..53 and 4 on 10..13), PCINT9..10 (14, 15), PCINT16..23
  // (port K, A8..A15): 18 pins of the board reach one (datasheet table 1-1; PCINT8 is RX0).
  EXPECT_EQ(pin_change_pins, 18);
}

}  // namespace
}  // namespace sear
