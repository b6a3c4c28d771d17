/* Arduino's Wire (TwoWire) for the simulated build, as a master on the HAL's I2C: 32-byte buffers,
 * repeated start with endTransmission(false), and endTransmission()'s codes: 0 success, 2 address
 * NACK, 3 data NACK, 4 other error; 1 (data too long) and 5 (timeout) never come, as from the
 * library on the chip (a 33rd byte is dropped by write()) and on a bus that does not hang. Slave mode (begin(address), onReceive, onRequest) is refused at run time. */
#ifndef TwoWire_h
#define TwoWire_h

#include <stdint.h>

#include "Stream.h"

#define BUFFER_LENGTH 32
#define WIRE_HAS_END 1
#define WIRE_HAS_TIMEOUT 1

class TwoWire : public Stream {
 public:
  void begin();
  void begin(uint8_t address);
  void begin(int address) { begin(static_cast<uint8_t>(address)); }
  void end();
  void setClock(uint32_t clock);
  void setWireTimeout(uint32_t timeout = 25000, bool reset_with_timeout = false);
  bool getWireTimeoutFlag() { return false; }
  void clearWireTimeoutFlag() {}
  void beginTransmission(uint8_t address);
  void beginTransmission(int address) { beginTransmission(static_cast<uint8_t>(address)); }
  uint8_t endTransmission(uint8_t sendStop);
  uint8_t endTransmission() { return endTransmission(true); }
  uint8_t requestFrom(uint8_t address, uint8_t quantity, uint32_t iaddress, uint8_t isize, uint8_t sendStop);
  uint8_t requestFrom(uint8_t address, uint8_t quantity, uint8_t sendStop) {
    return requestFrom(address, quantity, 0, 0, sendStop);
  }
  uint8_t requestFrom(uint8_t address, uint8_t quantity) { return requestFrom(address, quantity, 0, 0, true); }
  uint8_t requestFrom(int address, int quantity) {
    return requestFrom(static_cast<uint8_t>(address), static_cast<uint8_t>(quantity), 0, 0, true);
  }
  uint8_t requestFrom(int address, int quantity, int sendStop) {
    return requestFrom(static_cast<uint8_t>(address), static_cast<uint8_t>(quantity), 0, 0,
                       static_cast<uint8_t>(sendStop));
  }
  size_t write(uint8_t byte) override;
  size_t write(const uint8_t *data, size_t quantity) override;
  int available() override;
  int read() override;
  int peek() override;
  void flush() override {}
  void onReceive(void (*)(int));
  void onRequest(void (*)(void));
  size_t write(unsigned long n) { return write(static_cast<uint8_t>(n)); }
  size_t write(long n) { return write(static_cast<uint8_t>(n)); }
  size_t write(unsigned int n) { return write(static_cast<uint8_t>(n)); }
  size_t write(int n) { return write(static_cast<uint8_t>(n)); }
  using Print::write;

 private:
  uint8_t rx_[BUFFER_LENGTH];
  uint8_t rx_index_ = 0;
  uint8_t rx_length_ = 0;
  uint8_t tx_address_ = 0;
  uint8_t tx_[BUFFER_LENGTH];
  uint8_t tx_length_ = 0;
  bool transmitting_ = false;
};

extern TwoWire Wire;

#endif
