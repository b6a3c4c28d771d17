/* The SPI master: each transfer exchanges a byte with the device whose chip-select pin the
 * firmware holds LOW, and takes its 8 clock periods. With none selected MISO idles high and the
 * transfer reads 0xFF, as on a bench board. */
#include <hal/spi.h>

#include "mcu.h"

void spi_begin(uint8_t mode, uint32_t clock_hz) {
  mcu_enter(SEAR_CALL_spi_begin);
  if (mode > 3) mcu_fatal("spi_begin(%u, ...): SPI modes are 0..3", mode);
  /* The chip divides 16 MHz by 2, 4, ... 128: the fastest not above the request. */
  uint32_t hz = 8000000;
  while (hz > clock_hz && hz > 125000) hz /= 2;
  sear_mcu.spi_clock_hz = hz;
}

uint8_t spi_transfer(uint8_t out) {
  const int64_t now = mcu_enter(SEAR_CALL_spi_transfer);
  if (!sear_mcu.spi_clock_hz) mcu_fatal("spi_transfer: call spi_begin() first");
  const int miso = mcu_devices_spi_transfer(out, sear_mcu.spi_clock_hz, now);
  mcu_advance_to(now + (int64_t)(8ull * 1000000000ull / sear_mcu.spi_clock_hz));
  return miso < 0 ? 0xFF : (uint8_t)miso;
}
