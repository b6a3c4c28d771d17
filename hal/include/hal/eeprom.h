/* The ATmega2560's 4 KiB EEPROM: erased cells read 0xFF. A write takes the chip's 3.3 ms of
 * erase-and-write; it runs on its own, and the next access waits for it, as avr-libc's
 * eeprom_*_byte() do. In the simulator the contents last one run, or persist per MCU in a file
 * when the project asks for it (docs/arduino.md). */
#ifndef SEAR_HAL_EEPROM_H
#define SEAR_HAL_EEPROM_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HAL_EEPROM_SIZE 4096

uint8_t eeprom_read(uint16_t address);
void eeprom_write(uint16_t address, uint8_t value);

#ifdef __cplusplus
}
#endif
#endif
