/* <avr/interrupt.h> on the host build of the Arduino layer: including it is harmless (Debian's EEPROM
 * library does), but every register and ISR() it would have given is refused where it is used
 * (sear_registers_refused.h). */
#ifndef SEAR_ARDUINO_AVR_INTERRUPT_H
#define SEAR_ARDUINO_AVR_INTERRUPT_H
#include <hal/irq.h>
#include <sear_registers_refused.h>

/* The global interrupt flag is no register access: it is the HAL's. */
#define cli() irq_disable()
#define sei() irq_enable()
#endif
