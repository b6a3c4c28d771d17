/* Everything a firmware needs in one include: see each header for its peripheral. */
#ifndef SEAR_HAL_H
#define SEAR_HAL_H

#include <hal/system.h>
#include <hal/time.h>
#include <hal/gpio.h>
#include <hal/adc.h>
#include <hal/pwm.h>
#include <hal/uart.h>
#include <hal/spi.h>
#include <hal/i2c.h>
#include <hal/irq.h>
#include <hal/can.h>
#include <hal/pulse.h>
#include <hal/eeprom.h>
#include <hal/soft_uart.h>

#endif
