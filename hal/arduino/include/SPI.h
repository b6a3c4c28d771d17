/* Arduino's SPI library for the simulated build, on the HAL's SPI master: SPISettings (clock, bit
 * order, mode), transactions, transfer/transfer16/transfer(buffer, n). Chip selects are the
 * sketch's own digitalWrite()s, as on the board. */
#ifndef _SPI_H_INCLUDED
#define _SPI_H_INCLUDED

#include <stddef.h>
#include <stdint.h>

#define SPI_HAS_TRANSACTION 1
#define SPI_MODE0 0x00
#define SPI_MODE1 0x04
#define SPI_MODE2 0x08
#define SPI_MODE3 0x0C
#define SPI_CLOCK_DIV4 0x00
#define SPI_CLOCK_DIV16 0x01
#define SPI_CLOCK_DIV64 0x02
#define SPI_CLOCK_DIV128 0x03
#define SPI_CLOCK_DIV2 0x04
#define SPI_CLOCK_DIV8 0x05
#define SPI_CLOCK_DIV32 0x06

class SPISettings {
 public:
  SPISettings(uint32_t clock, uint8_t bitOrder, uint8_t dataMode) : clock_(clock), bit_order_(bitOrder), mode_(dataMode) {}
  SPISettings() : SPISettings(4000000, 1 /* MSBFIRST */, SPI_MODE0) {}

 private:
  uint32_t clock_;
  uint8_t bit_order_;
  uint8_t mode_;
  friend class SPIClass;
};

class SPIClass {
 public:
  static void begin();
  static void end();
  static void beginTransaction(SPISettings settings);
  static void endTransaction();
  static uint8_t transfer(uint8_t data);
  static uint16_t transfer16(uint16_t data);
  static void transfer(void *buf, size_t count);
  static void setBitOrder(uint8_t bitOrder);
  static void setDataMode(uint8_t dataMode);
  static void setClockDivider(uint8_t clockDiv);
  static void usingInterrupt(uint8_t) {}
  static void notUsingInterrupt(uint8_t) {}
};

extern SPIClass SPI;

#endif
