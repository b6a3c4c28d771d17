/* Serial, Serial1, Serial2, Serial3: the Mega's four USARTs as Arduino streams on the HAL's UARTs
 * (hal/uart.h): 64-byte buffers each way, 8N1 only. */
#ifndef HardwareSerial_h
#define HardwareSerial_h

#include <stdint.h>

#include "Stream.h"

/* begin()'s frame formats: only 8N1 is modelled, the others are refused at run time. */
#define SERIAL_8N1 0x06

class HardwareSerial : public Stream {
 public:
  explicit HardwareSerial(uint8_t port) : port_(port) {}
  void begin(unsigned long baud) { begin(baud, SERIAL_8N1); }
  void begin(unsigned long baud, uint8_t config);
  void end();
  int available() override;
  int peek() override;
  int read() override;
  int availableForWrite();
  void flush() override;
  size_t write(uint8_t byte) override;
  size_t write(unsigned long n) { return write((uint8_t)n); }
  size_t write(long n) { return write((uint8_t)n); }
  size_t write(unsigned int n) { return write((uint8_t)n); }
  size_t write(int n) { return write((uint8_t)n); }
  using Print::write;
  /* `while (!Serial)`: a Mega's USART is always ready. */
  operator bool() { return true; }

 private:
  uint8_t port_;
  int peeked_ = -1; /* a byte peek() took from the HAL's buffer, handed out first */
  bool begun_ = false;
};

extern HardwareSerial Serial;
extern HardwareSerial Serial1;
extern HardwareSerial Serial2;
extern HardwareSerial Serial3;

/* Called after each loop() when its port has bytes waiting, if the sketch defines it. */
extern void serialEvent() __attribute__((weak));
extern void serialEvent1() __attribute__((weak));
extern void serialEvent2() __attribute__((weak));
extern void serialEvent3() __attribute__((weak));
void serialEventRun();

#endif
