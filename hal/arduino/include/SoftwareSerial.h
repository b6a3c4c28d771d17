/* Arduino's SoftwareSerial for the simulated build: the library's interface, so that a sketch
 * using it builds, and a refusal at begin() naming the call. A soft UART needs a device that
 * drives a plain pin bit by bit, which SEAR's devices cannot yet do (docs/arduino.md, "Not yet"). */
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
  bool listen() { return false; }
  void end() {}
  bool isListening() { return false; }
  bool stopListening() { return false; }
  bool overflow() { return false; }
  int peek() { return -1; }

  // Before begin() the library's write() fails (its bit delay is 0) and nothing is received.
  virtual size_t write(uint8_t) {
    setWriteError();
    return 0;
  }
  virtual int read() { return -1; }
  virtual int available() { return 0; }
  virtual void flush() {}
  operator bool() { return true; }

  using Print::write;

 private:
  uint8_t receive_pin_;
  uint8_t transmit_pin_;
};

#endif
