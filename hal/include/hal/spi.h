/* The SPI master (MOSI 51, MISO 50, SCK 52 on a Mega). Select a device by driving its chip-select
 * pin LOW with digital_write() around the transfers, as on the real board. */
#ifndef SEAR_HAL_SPI_H
#define SEAR_HAL_SPI_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* mode 0..3 (clock polarity and phase); clock is rounded down to F_CPU / 2^n. */
void spi_begin(uint8_t mode, uint32_t clock_hz);
uint8_t spi_transfer(uint8_t out); /* returns the byte clocked in meanwhile */

#ifdef __cplusplus
}
#endif
#endif
