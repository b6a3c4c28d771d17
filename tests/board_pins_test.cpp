// The loader's table of the Mega 2560's PWM pins (sim/scene/board_pins.hpp) is the one the
// firmware's side refuses pwm_write() by (hal/runtime/board.c), pin for pin: a project the
// loader passes must not stop its firmware, and one it refuses must be one that would.
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

}  // namespace
}  // namespace sear
