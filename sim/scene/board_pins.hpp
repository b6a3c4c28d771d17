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

// Pins with a pin-change interrupt (PCINT0..3 on 50..53, PCINT4..7 and 9..10 on 10..15, PCINT16..23
// on A8..A15 = 62..69), the only ones a soft UART can receive on; hal/runtime/board.c keeps the same
// table (board_has_pin_change), held equal by tests/board_pins_test.cpp.
inline bool mega2560_has_pin_change(int pin) {
  return (pin >= 10 && pin <= 15) || (pin >= 50 && pin <= 53) || (pin >= 62 && pin <= 69);
}

// The pins of the chip's own buses (datasheet table 1-1, the board's silkscreen): a device on a
// bus is wired to them, and firmware that drives them (an AVR image setting up its SPI or USART)
// drives that device, not a pin nobody is wired to.
inline int mega2560_uart_rx_pin(int port) {
  static const int pins[4] = {0, 19, 17, 15};
  return pins[port];
}
inline int mega2560_uart_tx_pin(int port) {
  static const int pins[4] = {1, 18, 16, 14};
  return pins[port];
}
constexpr int kMega2560SpiPins[] = {50, 51, 52, 53};  // MISO, MOSI, SCK, SS
constexpr int kMega2560I2cPins[] = {20, 21};          // SDA, SCL

}  // namespace sear
