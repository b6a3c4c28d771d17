/* The devices whose models run in the firmware's process (DESIGN.md, "Where device models run"):
 * each wired input gets its model's state here, takes the simulator's samples of physical truth,
 * sees the pins the firmware drives to it, and puts its own levels, volts and edges on the board
 * at their sub-quantum times. One entry per input kind in devices.c's table.
 *
 * The entries serve every engine: they reach the chip only through the small board interface at
 * the end of this file, which the native runtime (pins.c) and the AVR engine (engines/avr)
 * each implement, so a device kind added once works on both. */
#ifndef SEAR_HAL_RUNTIME_DEVICES_H
#define SEAR_HAL_RUNTIME_DEVICES_H

#include <stdint.h>

#include "devices/hcsr04.h"
#include "devices/hmc5883l.h"
#include "devices/maxbotix_lv_ez.h"
#include "devices/mpu6000.h"
#include "devices/qmc5883l.h"
#include "devices/quadrature_encoder.h"
#include "devices/sharp_gp2d15.h"
#include "devices/uart_pins.h"
#include "lockstep_link.h"

#define MCU_FLOATING 0xFF /* nothing outside drives the pin */
#define MCU_TIME_NEVER INT64_MAX
#define MCU_NO_DEVICE 0xFF /* no device listens to the pin */

/* The state of one wired input's model (devices.c says which member its kind uses). */
struct mcu_device {
  union {
    struct gp2d15 gp2d15;
    struct hcsr04 hcsr04;
    struct maxbotix_lv_ez maxbotix;
    struct quadrature_encoder encoder;
    struct mpu6000 mpu;
    struct hmc5883l hmc;
    struct qmc5883l qmc;
    struct uart_pins line;
  } u;
  int64_t analog_shown_ns; /* an analog output's last update */
  int64_t next_ns;         /* its next event of its own (devices.c keeps it current) */
  double out_v;            /* the volts an analog output last put on its channel */
  uint8_t out_level;       /* the level a digital output last drove, or MCU_FLOATING */
};

/* Sets up every input the simulator wired in `link`, at start-up; the link is kept for the
 * inputs' wiring and for publishing readings (readings.h). */
void mcu_devices_init(struct sear_link *link);
struct sear_link *mcu_devices_link(void);
/* Input i's model state, for its reading. */
const struct mcu_device *mcu_device_state(uint32_t i);
/* The time of the device operation in progress (a sample, an edge, a pin or bus access): when a
 * level a device puts on the board now changes. */
int64_t mcu_devices_time_ns(void);
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
/* Whether a device answers to `address` on I2C (the address byte's acknowledge). */
int mcu_devices_i2c_present(uint8_t address);

/* The board interface: what the entries need from the engine that hosts them. */
/* A device drives `level` (0/1) onto the pin, or MCU_FLOATING to let go of it. */
void board_drive_pin(uint8_t pin, uint8_t level);
/* A device puts `volts` on ADC channel `channel`. */
void board_set_analog(uint8_t channel, double volts);
/* Whether the firmware drives the pin as an output at LOW (an SPI chip select taken). */
int board_output_low(uint8_t pin);
/* A device's next event of its own now falls at t_ns: the engine must look again by then. */
void board_device_event_at(int64_t t_ns);

#endif
