// Wire on the HAL's I2C master: the library's buffering and return codes; the bus's timing and the
// devices' answers come from the HAL.
#include <Arduino.h>
#include <Wire.h>
#include <hal/i2c.h>

#include "refuse.hpp"

TwoWire Wire;

// The library's begin() sets 100 kHz (TWBR 72 at 16 MHz).
void TwoWire::begin() {
  i2c_begin(100000);
  rx_index_ = rx_length_ = tx_length_ = 0;
}

void TwoWire::begin(uint8_t) { sear_arduino_refuse("Wire.begin(address)", "I2C slave mode is not modelled"); }

void TwoWire::end() {}

// The TWI makes F_CPU / (16 + 2 * TWBR) for the library's TWBR = ((F_CPU / clock) - 16) / 2; the
// HAL takes the rate itself and bounds it to 10..400 kHz as the library's users must.
void TwoWire::setClock(uint32_t clock) { i2c_begin(clock); }

// The modelled bus never stretches the clock or loses arbitration, so no transaction times out.
void TwoWire::setWireTimeout(uint32_t, bool) {}

void TwoWire::beginTransmission(uint8_t address) {
  transmitting_ = true;
  tx_address_ = address;
  tx_length_ = 0;
}

// The library's codes from twi_writeTo: 2 address NACK, 3 data NACK, 4 other. Its write() past the
// 32-byte buffer sets a write error and drops the byte, and the 32 kept still go out with code 0:
// 1 ("data too long") never comes from this library on the chip either.
uint8_t TwoWire::endTransmission(uint8_t sendStop) {
  const int8_t result = sendStop ? i2c_write(tx_address_, tx_, tx_length_) : i2c_write_nostop(tx_address_, tx_, tx_length_);
  transmitting_ = false;
  tx_length_ = 0;
  if (result == I2C_NACK) return 2;
  if (result == I2C_NACK_DATA) return 3;
  return result == I2C_OK ? 0 : 4;
}

// A request past the buffer is cut to 32 bytes, as the library does. With isize, the register
// address goes out first (most significant byte first) and a repeated start begins the read.
uint8_t TwoWire::requestFrom(uint8_t address, uint8_t quantity, uint32_t iaddress, uint8_t isize, uint8_t sendStop) {
  if (!sendStop) sear_arduino_refuse("Wire.requestFrom(..., false)", "a read that keeps the bus is not modelled");
  if (quantity > BUFFER_LENGTH) quantity = BUFFER_LENGTH;
  if (isize > 3) isize = 3;
  int8_t result;
  if (isize) {
    uint8_t reg[3];
    for (uint8_t i = 0; i < isize; ++i) reg[i] = static_cast<uint8_t>(iaddress >> (8 * (isize - 1 - i)));
    result = i2c_write_read(address, reg, isize, rx_, quantity);
  } else {
    result = i2c_read(address, rx_, quantity);
  }
  rx_index_ = 0;
  rx_length_ = result == I2C_OK ? quantity : 0;
  return rx_length_;
}

size_t TwoWire::write(uint8_t value) {
  if (!transmitting_) sear_arduino_refuse("Wire.write()", "slave mode (writing outside beginTransmission) is not modelled");
  if (tx_length_ >= BUFFER_LENGTH) {
    setWriteError();
    return 0;
  }
  tx_[tx_length_++] = value;
  return 1;
}

size_t TwoWire::write(const uint8_t* data, size_t quantity) {
  size_t n = 0;
  while (n < quantity && write(data[n])) ++n;
  return n;
}

int TwoWire::available() { return rx_length_ - rx_index_; }

int TwoWire::read() { return rx_index_ < rx_length_ ? rx_[rx_index_++] : -1; }

int TwoWire::peek() { return rx_index_ < rx_length_ ? rx_[rx_index_] : -1; }

void TwoWire::onReceive(void (*)(int)) { sear_arduino_refuse("Wire.onReceive()", "I2C slave mode is not modelled"); }

void TwoWire::onRequest(void (*)(void)) { sear_arduino_refuse("Wire.onRequest()", "I2C slave mode is not modelled"); }
