/* Arduino's SoftwareSerial for the simulated build: the library's interface on the HAL's soft
 * UART (hal/soft_uart.h): receive on the pin-change pins only, one listener at a time, a 64-byte
 * ring, and interrupts held off while a byte is sent, as the library does on the chip. */
#ifndef SoftwareSerial_h
#define SoftwareSerial_h

#include <stdint.h>

#include "Stream.h"

#define _SS_MAX_RX_BUFF 64

class SoftwareSerial : public Stream {
 public:
  SoftwareSerial(uint8_t receivePin, uint8_t transmitPin, bool inverse_logic = false);
  ~SoftwareSerial() {}
  void begin(long speed);
  bool listen();
  void end();
  bool isListening();
  bool stopListening();
  bool overflow();
  int peek();

  // Before begin() the library's write() fails (its bit delay is 0) and nothing is received.
  virtual size_t write(uint8_t byte);
  virtual int read();
  virtual int available();
  virtual void flush() {}  // the library buffers nothing to send
  operator bool() { return true; }

  using Print::write;

 private:
  uint8_t receive_pin_;
  uint8_t transmit_pin_;
  bool inverse_logic_;
  int line_ = -1;  // the HAL's soft UART id once begun
};

#endif
