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
#include <sim_cycle_timers.h>
#include <sim_io.h>

#include "devices.h"
#include "engine.h"

/* SPCR, SPSR, SPDR, TWBR, TWSR and TWCR data addresses (ATmega2560 register summary). */
#define SPCR 0x4C
#define SPSR 0x4D
#define SPDR 0x4E
#define TWBR 0xB8
#define TWSR 0xB9
#define TWCR 0xBC
#define TWINT 0x80
#define TWSTA 0x20
#define TWSTO 0x10

/* TWSR status codes of a master transmitter (datasheet table 24-3). */
#define MT_SLA_ACK 0x18
#define MT_SLA_NACK 0x20
#define MT_DATA_ACK 0x28
#define MT_DATA_NACK 0x30

static avr_irq_t *spi_in, *twi_in;

/* Cycles per SCK period: {4, 16, 64, 128}[SPR1:0], halved by SPI2X (datasheet table 21-5). */
static uint32_t sck_cycles(void) {
  static const uint32_t div[4] = {4, 16, 64, 128};
  const uint8_t *d = engine.avr->data;
  return d[SPSR] & 1 ? div[d[SPCR] & 3] / 2 : div[d[SPCR] & 3];
}

static uint32_t sck_hz(void) { return (uint32_t)(engine.clock_hz / sck_cycles()); }

/* Cycles per SCL period: 16 + 2 TWBR 4^TWPS (datasheet 24.5.2, "Bit Rate Generator Unit"). */
static uint32_t scl_cycles(void) {
  const uint8_t *d = engine.avr->data;
  return 16u + 2u * d[TWBR] * (1u << (2u * (d[TWSR] & 3u)));
}

/* simavr 1.6 paces its SPI and TWI with fixed delays, not the bus clock: 100 us for every SPI
 * byte (at the 8 MHz SCK an MPU-6000 is read with, 100 times the chip's 1 us), 9 us for every
 * TWI byte (the chip takes 9 SCL periods: 22.5 us at 400 kHz, 90 us at 100 kHz). Each module's
 * only cycle timer (its param is the module) is moved to when the chip finishes the byte. */
static void retime(void *module, avr_cycle_count_t cycles) {
  for (avr_cycle_timer_slot_p t = engine.avr->cycle_timers.timer; t; t = t->next) {
    if (t->param != module) continue;
    const avr_cycle_timer_t fn = t->timer;
    avr_cycle_timer_cancel(engine.avr, fn, module);
    avr_cycle_timer_register(engine.avr, cycles, fn, module);
    return;
  }
}

static avr_io_write_t spdr_write;
static void *spdr_param;

/* A byte is shifted out in 8 SCK periods, and SPIF rises at its end. */
static void on_spdr_write(avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param) {
  (void)param;
  spdr_write(avr, addr, v, spdr_param);
  retime(spdr_param, 8u * sck_cycles());
}

static void on_spi(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  (void)param;
  const int miso = mcu_devices_spi_transfer((uint8_t)value, sck_hz(), engine_now_ns());
  avr_raise_irq(spi_in, miso < 0 ? 0xFF : (uint32_t)miso); /* MISO idles high */
}

static struct {
  int sla_w;       /* SLA+W is on the bus; the next status is its own */
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
    twi.sla_w = !twi.reading;
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

/* simavr 1.6 reports SLA+W as if it were a data byte, 28h or 30h for ACK or NACK, where the chip
 * gives 18h or 20h (datasheet table 24-3), and a master that checks TWSR as the datasheet says
 * (the HAL, Wire, Fleury's twimaster) takes a present device for a failed transfer. Every status
 * comes through here just after simavr wrote it to TWSR, before TWINT is raised, so the address's
 * status is set right before the firmware can read it. The prescaler bits (TWPS1:0) stay. */
static void on_twi_status(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  (void)param;
  if (!twi.sla_w) return;
  twi.sla_w = 0;
  uint8_t *twsr = &engine.avr->data[TWSR];
  if (value == MT_DATA_ACK) *twsr = (uint8_t)((*twsr & 0x07) | MT_SLA_ACK);
  else if (value == MT_DATA_NACK) *twsr = (uint8_t)((*twsr & 0x07) | MT_SLA_NACK);
}

/* The chip clears TWINT when the firmware writes it one (TWCR in the datasheet), and that starts
 * the next bus step. simavr 1.6 marks the TWI vector's flag sticky (the ISR must not clear it, as on
 * the chip) and so never clears it at all: a master polling TWINT right after its write sees the
 * previous step's flag and status. simavr's own write runs first (it reads the flag as written to
 * decide whether a step was asked for); then the flag goes. Every status that sets it again comes
 * from a cycle timer, after this. */
static avr_io_write_t twcr_write;
static void *twcr_param;

static void on_twcr_write(avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param) {
  (void)param;
  const uint8_t flag_was = avr->data[TWCR] & TWINT;
  twcr_write(avr, addr, v, twcr_param);
  if (!(v & TWINT)) return;
  avr->data[TWCR] = (uint8_t)(avr->data[TWCR] & ~TWINT);
  /* A byte (address or data, and its acknowledge) is 9 SCL periods; a START keeps simavr's
   * timing. */
  if (flag_was && !(v & (TWSTA | TWSTO))) retime(twcr_param, 9u * scl_cycles());
}

void avr_buses_init(void) {
  spi_in = avr_io_getirq(engine.avr, AVR_IOCTL_SPI_GETIRQ(0), SPI_IRQ_INPUT);
  twi_in = avr_io_getirq(engine.avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_INPUT);
  if (!spi_in || !twi_in) engine_fatal("libsimavr's ATmega2560 has no SPI or TWI");
  avr_irq_register_notify(avr_io_getirq(engine.avr, AVR_IOCTL_SPI_GETIRQ(0), SPI_IRQ_OUTPUT), on_spi, NULL);
  avr_irq_register_notify(avr_io_getirq(engine.avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_OUTPUT), on_twi, NULL);
  avr_irq_register_notify(avr_io_getirq(engine.avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_STATUS), on_twi_status, NULL);
  memset(&twi, 0, sizeof twi);
  const avr_io_addr_t spdr = AVR_DATA_TO_IO(SPDR);
  spdr_write = engine.avr->io[spdr].w.c;
  spdr_param = engine.avr->io[spdr].w.param;
  if (!spdr_write) engine_fatal("libsimavr's ATmega2560 has no SPDR");
  engine.avr->io[spdr].w.c = on_spdr_write;
  const avr_io_addr_t twcr = AVR_DATA_TO_IO(TWCR);
  twcr_write = engine.avr->io[twcr].w.c;
  twcr_param = engine.avr->io[twcr].w.param;
  if (!twcr_write) engine_fatal("libsimavr's ATmega2560 has no TWCR");
  engine.avr->io[twcr].w.c = on_twcr_write;
}
