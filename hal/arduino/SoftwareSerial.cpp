// SoftwareSerial refused at begin(), with the pins and the way round named: the soft UART is not
// modelled yet, and a sketch that believed it sent or received would run silently useless.
#include <SoftwareSerial.h>

#include <string>

#include "refuse.hpp"

SoftwareSerial::SoftwareSerial(uint8_t receivePin, uint8_t transmitPin, bool)
    : receive_pin_(receivePin), transmit_pin_(transmitPin) {}

void SoftwareSerial::begin(long speed) {
  const std::string call = "SoftwareSerial(" + std::to_string(receive_pin_) + ", " + std::to_string(transmit_pin_) +
                           ").begin(" + std::to_string(speed) + ")";
  sear_arduino_refuse(call.c_str(),
                      "the soft UART is not modelled yet (no device can drive a plain pin as a UART); wire the "
                      "device to Serial1, Serial2 or Serial3 (RX 19, 17, 15; TX 18, 16, 14) instead");
}
