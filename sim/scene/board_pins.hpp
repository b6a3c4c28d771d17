// The reference board's pins as a project file may wire them (Arduino Mega 2560, ATmega2560), for
// the loader to refuse what the firmware's side would refuse only once the run is under way.
#pragma once

#include <string>

namespace sear {

// Pins that reach a timer's output compare unit (analogWrite on the board): 2..13 and 44..46, as
// the datasheet's table 1-1 and the board's schematic wire them. The firmware's side keeps the same
// table (hal/runtime/board.c, which sim/ may not include); tests/board_pins_test.cpp holds them equal.
inline bool mega2560_has_pwm(int pin) { return (pin >= 2 && pin <= 13) || (pin >= 44 && pin <= 46); }

// The PWM pins as a person reads them in a message.
inline const char* mega2560_pwm_pins() { return "2..13 and 44..46"; }

}  // namespace sear
