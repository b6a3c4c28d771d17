/* avr-libc's EEPROM calls on the HAL's EEPROM (hal/eeprom.h), so that Debian's EEPROM library
 * (libraries/EEPROM/src/EEPROM.h) compiles unchanged for the simulated build: an "address" here
 * is the cell's number cast to a pointer, as on the chip. */
#ifndef SEAR_ARDUINO_AVR_EEPROM_H
#define SEAR_ARDUINO_AVR_EEPROM_H

#include <hal/eeprom.h>
#include <stddef.h>
#include <stdint.h>

#define E2END (HAL_EEPROM_SIZE - 1)

static inline uint16_t sear_eeprom_cell(const volatile void *p) { return (uint16_t)(uintptr_t)p; }

static inline uint8_t eeprom_read_byte(const uint8_t *p) { return eeprom_read(sear_eeprom_cell(p)); }
static inline void eeprom_write_byte(uint8_t *p, uint8_t value) { eeprom_write(sear_eeprom_cell(p), value); }
static inline void eeprom_update_byte(uint8_t *p, uint8_t value) {
  if (eeprom_read_byte(p) != value) eeprom_write_byte(p, value);
}
static inline void eeprom_read_block(void *dst, const void *src, size_t n) {
  for (size_t i = 0; i < n; ++i) ((uint8_t *)dst)[i] = eeprom_read((uint16_t)(sear_eeprom_cell(src) + i));
}
static inline void eeprom_update_block(const void *src, void *dst, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    const uint16_t cell = (uint16_t)(sear_eeprom_cell(dst) + i);
    if (eeprom_read(cell) != ((const uint8_t *)src)[i]) eeprom_write(cell, ((const uint8_t *)src)[i]);
  }
}
static inline void eeprom_write_block(const void *src, void *dst, size_t n) { eeprom_update_block(src, dst, n); }

#endif
