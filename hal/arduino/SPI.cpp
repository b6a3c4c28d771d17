// SPI on the HAL's master. The HAL shifts most significant bit first; LSBFIRST is the same wire
// with each byte mirrored both ways.
#include <Arduino.h>
#include <SPI.h>
#include <hal/spi.h>

SPIClass SPI;

namespace {

uint32_t clock_hz = 4000000; // the library's default: F_CPU / 4
uint8_t mode = 0;
bool lsb_first = false;

uint8_t mirrored(uint8_t b) {
  b = static_cast<uint8_t>((b & 0xF0) >> 4 | (b & 0x0F) << 4);
  b = static_cast<uint8_t>((b & 0xCC) >> 2 | (b & 0x33) << 2);
  return static_cast<uint8_t>((b & 0xAA) >> 1 | (b & 0x55) << 1);
}

void apply() { spi_begin(mode, clock_hz); }

}  // namespace

// As the library: SS becomes an output driven HIGH (so the AVR stays master), SCK and MOSI
// outputs.
void SPIClass::begin() {
  digitalWrite(SS, HIGH);
  pinMode(SS, OUTPUT);
  apply();
}

void SPIClass::end() {}

void SPIClass::beginTransaction(SPISettings settings) {
  clock_hz = settings.clock_;
  mode = static_cast<uint8_t>(settings.mode_ >> 2);
  lsb_first = settings.bit_order_ == LSBFIRST;
  apply();
}

void SPIClass::endTransaction() {}

uint8_t SPIClass::transfer(uint8_t data) {
  if (!lsb_first) return spi_transfer(data);
  return mirrored(spi_transfer(mirrored(data)));
}

uint16_t SPIClass::transfer16(uint16_t data) {
  if (lsb_first) {
    const uint8_t low = transfer(static_cast<uint8_t>(data));
    return static_cast<uint16_t>(transfer(static_cast<uint8_t>(data >> 8)) << 8 | low);
  }
  const uint8_t high = transfer(static_cast<uint8_t>(data >> 8));
  return static_cast<uint16_t>(high << 8 | transfer(static_cast<uint8_t>(data)));
}

void SPIClass::transfer(void* buf, size_t count) {
  uint8_t* bytes = static_cast<uint8_t*>(buf);
  for (size_t i = 0; i < count; ++i) bytes[i] = transfer(bytes[i]);
}

void SPIClass::setBitOrder(uint8_t bitOrder) { lsb_first = bitOrder == LSBFIRST; }

void SPIClass::setDataMode(uint8_t dataMode) {
  mode = static_cast<uint8_t>(dataMode >> 2);
  apply();
}

// SPCR's SPR1:0 and SPSR's SPI2X, as the library packs them: F_CPU divided by 2..128.
void SPIClass::setClockDivider(uint8_t clockDiv) {
  static const uint8_t kDivider[8] = {4, 16, 64, 128, 2, 8, 32, 64};
  clock_hz = F_CPU / kDivider[clockDiv & 7];
  apply();
}
