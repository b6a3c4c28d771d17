/* SPI and TWI masters of the chip, to the device models of the native engine through the same
 * entries (devices.h): an SPI byte is exchanged with the selected device as it is shifted; a
 * TWI transaction's bytes are acknowledged as they go, and what it wrote reaches the device at
 * its STOP or repeated START, as one write, so that a register pointer and the data after it
 * land as the native engine's i2c_write delivers them. */
#include <stdint.h>
#include <string.h>

#include <avr_spi.h>
#include <avr_twi.h>
#include <sim_avr.h>
#include <sim_io.h>

#include "devices.h"
#include "engine.h"

/* SPCR and SPSR data addresses (ATmega2560 register summary). */
#define SPCR 0x4C
#define SPSR 0x4D

static avr_irq_t *spi_in, *twi_in;

/* SCK = f / {4, 16, 64, 128}[SPR1:0], doubled by SPI2X (datasheet table 21-5). */
static uint32_t sck_hz(void) {
  static const uint32_t div[4] = {4, 16, 64, 128};
  const uint8_t *d = engine.avr->data;
  const uint32_t hz = (uint32_t)(engine.clock_hz / div[d[SPCR] & 3]);
  return d[SPSR] & 1 ? hz * 2 : hz;
}

static void on_spi(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  (void)param;
  const int miso = mcu_devices_spi_transfer((uint8_t)value, sck_hz(), engine_now_ns());
  avr_raise_irq(spi_in, miso < 0 ? 0xFF : (uint32_t)miso); /* MISO idles high */
}

static struct {
  int addressed;   /* a device acknowledged the address */
  int reading;
  uint8_t address; /* 7-bit */
  uint8_t length;
  uint8_t data[255];
} twi;

static void finish_write(int64_t now) {
  if (twi.addressed && !twi.reading && twi.length) mcu_devices_i2c_write(twi.address, twi.data, twi.length, now);
  twi.length = 0;
  twi.addressed = 0;
}

static void on_twi(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  (void)param;
  avr_twi_msg_irq_t m;
  m.u.v = value;
  const int64_t now = engine_now_ns();
  const uint8_t msg = (uint8_t)m.u.twi.msg;
  if (msg & TWI_COND_STOP) {
    finish_write(now);
    return;
  }
  if (msg & TWI_COND_START) { /* SLA+R/W: a start or repeated start's address byte */
    finish_write(now);
    twi.address = (uint8_t)(m.u.twi.addr >> 1);
    twi.reading = m.u.twi.addr & 1;
    twi.addressed = mcu_devices_i2c_present(twi.address);
    if (twi.addressed) avr_raise_irq(twi_in, avr_twi_irq_msg(TWI_COND_ACK, (uint8_t)m.u.twi.addr, 1));
    return;
  }
  if (!twi.addressed) return; /* nobody drives SDA: the master reads NACK and 0xFF */
  if (msg & TWI_COND_WRITE) {
    if (twi.length < sizeof twi.data) twi.data[twi.length++] = (uint8_t)m.u.twi.data;
    avr_raise_irq(twi_in, avr_twi_irq_msg(TWI_COND_ACK, (uint8_t)m.u.twi.addr, 1));
  } else if (msg & TWI_COND_READ) {
    uint8_t byte = 0xFF;
    mcu_devices_i2c_read(twi.address, &byte, 1, now);
    avr_raise_irq(twi_in, avr_twi_irq_msg(TWI_COND_READ, (uint8_t)m.u.twi.addr, byte));
  }
}

void avr_buses_init(void) {
  spi_in = avr_io_getirq(engine.avr, AVR_IOCTL_SPI_GETIRQ(0), SPI_IRQ_INPUT);
  twi_in = avr_io_getirq(engine.avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_INPUT);
  if (!spi_in || !twi_in) engine_fatal("libsimavr's ATmega2560 has no SPI or TWI");
  avr_irq_register_notify(avr_io_getirq(engine.avr, AVR_IOCTL_SPI_GETIRQ(0), SPI_IRQ_OUTPUT), on_spi, NULL);
  avr_irq_register_notify(avr_io_getirq(engine.avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_OUTPUT), on_twi, NULL);
  memset(&twi, 0, sizeof twi);
}
