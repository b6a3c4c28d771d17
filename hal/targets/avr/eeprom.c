/* The EEPROM through avr-libc, which waits for a write still programming before each access. */
#include <hal/eeprom.h>

#include <avr/eeprom.h>
#include <stdint.h>

uint8_t eeprom_read(uint16_t address)
{
    if (address >= HAL_EEPROM_SIZE)
        return 0xFF;
    return eeprom_read_byte((const uint8_t *)(uintptr_t)address);
}

void eeprom_write(uint16_t address, uint8_t value)
{
    if (address < HAL_EEPROM_SIZE)
        eeprom_write_byte((uint8_t *)(uintptr_t)address, value);
}
