/* The devices whose models run in the firmware's process (DESIGN.md, "Where device models run"):
 * each wired input gets its model's state here, takes the simulator's samples of physical truth,
 * sees the pins the firmware drives to it, and puts its own levels and edges on pins at their
 * sub-quantum times. One entry per input kind in devices.c's table. */
#ifndef SEAR_HAL_RUNTIME_DEVICES_H
#define SEAR_HAL_RUNTIME_DEVICES_H

#include <stdint.h>

#include "mcu_state.h"

/* Sets up every input the simulator wired, from the link; at start-up. */
void mcu_devices_init(void);
/* A sample of truth for input s->input, now due. */
void mcu_devices_sample(const struct sear_link_sample *s);
/* The firmware drove `pin` to `level` (an output's new level) at t_ns. */
void mcu_devices_pin_written(uint8_t pin, uint8_t level, int64_t t_ns);
/* The earliest time a device has an edge or update of its own to make, MCU_TIME_NEVER if none. */
int64_t mcu_devices_next_event(void);
/* Makes every device event due by now_ns, in time order. */
void mcu_devices_run_due(int64_t now_ns);

/* SPI: the byte the selected device (its chip-select pin an output driven LOW) shifts out while
 * `mosi` goes in, at sck_hz; -1 when no device is selected (MISO then idles high). */
int mcu_devices_spi_transfer(uint8_t mosi, uint32_t sck_hz, int64_t t_ns);
/* I2C: a write or read transaction with the device at `address`; 0 when it acknowledged, -1 when
 * no device answers to that address. */
int mcu_devices_i2c_write(uint8_t address, const uint8_t *data, uint8_t length, int64_t t_ns);
int mcu_devices_i2c_read(uint8_t address, uint8_t *data, uint8_t length, int64_t t_ns);

#endif
