// The Mega's USARTs on the HAL's UARTs; serialEvent after each loop() as the core's main() does.
#include <Arduino.h>
#include <hal/uart.h>

#include "refuse.hpp"

HardwareSerial Serial(0);
HardwareSerial Serial1(1);
HardwareSerial Serial2(2);
HardwareSerial Serial3(3);

void HardwareSerial::begin(unsigned long baud, uint8_t config) {
  if (config != SERIAL_8N1) sear_arduino_refuse("Serial.begin(baud, config)", "only SERIAL_8N1 frames are modelled");
  uart_begin(port_, static_cast<uint32_t>(baud));
  begun_ = true;
}

// The core's end() waits for the bytes written and turns the port off; here the port keeps its
// rate, and bytes that arrive meanwhile wait as if it were on.
void HardwareSerial::end() {
  flush();
  begun_ = false;
  peeked_ = -1;
}

int HardwareSerial::available() { return uart_available(port_) + (peeked_ >= 0 ? 1 : 0); }

int HardwareSerial::peek() {
  if (peeked_ < 0) peeked_ = uart_read(port_);
  return peeked_;
}

int HardwareSerial::read() {
  if (peeked_ >= 0) {
    const int value = peeked_;
    peeked_ = -1;
    return value;
  }
  return uart_read(port_);
}

// The core's ring holds 63 of its 64 places; the HAL's ring all 64.
int HardwareSerial::availableForWrite() {
  const int space = uart_tx_space(port_);
  return space > 63 ? 63 : space;
}

void HardwareSerial::flush() { uart_flush(port_); }

// Before begin() the core's write() still queues into a transmitter that is off; the HAL drops
// such bytes, as nothing would leave the pin.
size_t HardwareSerial::write(uint8_t value) {
  uart_write(port_, value);
  return 1;
}

void serialEventRun() {
  if (serialEvent && Serial.available()) serialEvent();
  if (serialEvent1 && Serial1.available()) serialEvent1();
  if (serialEvent2 && Serial2.available()) serialEvent2();
  if (serialEvent3 && Serial3.available()) serialEvent3();
}
