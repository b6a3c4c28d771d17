// Arduino's SoftwareSerial on the HAL's soft UART (hal/soft_uart.h). A receive pin without a
// pin-change interrupt is refused at begin(), naming the call and the pins that have one: the
// library would send but never receive there, and a sketch waiting for bytes would run silently
// useless.
#include <SoftwareSerial.h>

#include <hal/soft_uart.h>

#include <string>

#include "refuse.hpp"

namespace {

// The ATmega2560's PCINT pins on the Mega board, as the library's documentation lists them.
bool has_pin_change(uint8_t pin) { return (pin >= 10 && pin <= 15) || (pin >= 50 && pin <= 53) || (pin >= 62 && pin <= 69); }

}  // namespace

SoftwareSerial::SoftwareSerial(uint8_t receivePin, uint8_t transmitPin, bool inverse_logic)
    : receive_pin_(receivePin), transmit_pin_(transmitPin), inverse_logic_(inverse_logic) {}

void SoftwareSerial::begin(long speed) {
  const std::string call = "SoftwareSerial(" + std::to_string(receive_pin_) + ", " + std::to_string(transmit_pin_) +
                           ").begin(" + std::to_string(speed) + ")";
  if (!has_pin_change(receive_pin_))
    sear_arduino_refuse(call.c_str(),
                        ("RX pin " + std::to_string(receive_pin_) +
                         " has no pin-change interrupt; the Mega receives on 10..15, 50..53, A8..A15")
                            .c_str());
  if (speed < 300 || speed > 115200)
    sear_arduino_refuse(call.c_str(), "the library's bit delays exist for 300..115200 baud");
  line_ = soft_uart_begin(receive_pin_, transmit_pin_, static_cast<uint32_t>(speed), inverse_logic_ ? 1 : 0);
}

bool SoftwareSerial::listen() { return line_ >= 0 && soft_uart_listen(static_cast<uint8_t>(line_)); }

bool SoftwareSerial::stopListening() { return line_ >= 0 && soft_uart_stop_listening(static_cast<uint8_t>(line_)); }

void SoftwareSerial::end() {
  if (line_ < 0) return;
  soft_uart_end(static_cast<uint8_t>(line_));
  line_ = -1;
}

bool SoftwareSerial::isListening() { return line_ >= 0 && soft_uart_is_listening(static_cast<uint8_t>(line_)); }

bool SoftwareSerial::overflow() { return line_ >= 0 && soft_uart_overflow(static_cast<uint8_t>(line_)); }

int SoftwareSerial::peek() { return line_ < 0 ? -1 : soft_uart_peek(static_cast<uint8_t>(line_)); }

int SoftwareSerial::read() { return line_ < 0 ? -1 : soft_uart_read(static_cast<uint8_t>(line_)); }

int SoftwareSerial::available() { return line_ < 0 ? 0 : soft_uart_available(static_cast<uint8_t>(line_)); }

size_t SoftwareSerial::write(uint8_t byte) {
  if (line_ < 0) {
    setWriteError();
    return 0;
  }
  soft_uart_write(static_cast<uint8_t>(line_), byte);
  return 1;
}
