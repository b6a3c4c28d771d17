/* <avr/io.h> on the host build of the Arduino layer: including it is harmless (Debian's EEPROM
 * library does), but every register and ISR() it would have given is refused where it is used
 * (sear_registers_refused.h). */
#ifndef SEAR_ARDUINO_AVR_IO_H
#define SEAR_ARDUINO_AVR_IO_H
#include <sear_registers_refused.h>
#endif
