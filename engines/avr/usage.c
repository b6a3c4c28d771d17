/* What the firmware used that leaves no event, for the run's wiring report (sear_link.usage): input
 * pins read through PINx or given a pin interrupt, and ADC channels converted. The native runtime
 * notes its HAL calls; here the registers tell. A PINx read marks every input of its port, so a
 * note may be missed, never made wrongly. */
#include <stdint.h>
#include <string.h>

#include <avr_adc.h>
#include <avr_ioport.h>
#include <sim_avr.h>
#include <sim_io.h>

#include "engine.h"

#define PORTS 11 /* A..L without I, in pins.c's order */
static const char port_names[PORTS] = {'A', 'B', 'C', 'D', 'E', 'F', 'G', 'H', 'J', 'K', 'L'};
enum { PB = 1, PD = 3, PE = 4, PJ = 8, PK = 9 };

static struct {
  avr_io_read_t read; /* simavr's own read of PINx, which ours wraps */
  void *param;
  avr_io_addr_t ddr;
} pin_regs[PORTS];

static void mark_read(int port, uint8_t bits) {
  for (int bit = 0; bit < 8; ++bit) {
    const uint8_t pin = avr_pin_at(port, bit);
    if ((bits >> bit & 1) && pin < SEAR_LINK_PINS) engine.link->usage.pin_read[pin] = 1;
  }
}

static uint8_t pin_read(avr_t *avr, avr_io_addr_t addr, void *param) {
  const int p = (int)(intptr_t)param;
  const uint8_t value = pin_regs[p].read ? pin_regs[p].read(avr, addr, pin_regs[p].param) : avr->data[addr];
  mark_read(p, (uint8_t)~avr->data[pin_regs[p].ddr]);
  return value;
}

static void adc_started(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  (void)param;
  union {
    avr_adc_mux_t mux;
    uint32_t raw;
  } e = {.raw = value};
  if (e.mux.kind == ADC_MUX_SINGLE && e.mux.src < 32) engine.link->usage.adc_read |= 1u << e.mux.src;
}

void avr_usage_init(void) {
  memset(pin_regs, 0, sizeof pin_regs);
  for (avr_io_t *io = engine.avr->io_port; io; io = io->next) {
    if (strcmp(io->kind, "port") != 0) continue;
    const avr_ioport_t *port = (const avr_ioport_t *)io;
    const char *at = memchr(port_names, port->name, PORTS);
    if (!at) continue;
    const int p = (int)(at - port_names);
    /* simavr refuses a second reader of an address, so ours takes its place and calls it. */
    const avr_io_addr_t reg = AVR_DATA_TO_IO(port->r_pin);
    pin_regs[p].read = engine.avr->io[reg].r.c;
    pin_regs[p].param = engine.avr->io[reg].r.param;
    pin_regs[p].ddr = port->r_ddr;
    engine.avr->io[reg].r.c = pin_read;
    engine.avr->io[reg].r.param = (void *)(intptr_t)p;
  }
  avr_irq_t *trigger = avr_io_getirq(engine.avr, AVR_IOCTL_ADC_GETIRQ, ADC_IRQ_OUT_TRIGGER);
  if (trigger) avr_irq_register_notify(trigger, adc_started, NULL);
  engine.link->usage.usage_kept = 1;
}

/* Pins given an interrupt (the datasheet's External Interrupts chapter: EIMSK's INT0..3 on PD0..3 and INT4..7 on PE4..7; PCICR
 * with PCMSK0 on PB0..7, PCMSK1 on PE0 and PJ0..6, PCMSK2 on PK0..7) count as read. */
void avr_usage_note_interrupts(void) {
  const uint8_t *d = engine.avr->data;
  const uint8_t eimsk = d[0x3D], pcicr = d[0x68];
  mark_read(PD, eimsk & 0x0F);
  mark_read(PE, eimsk & 0xF0);
  if (pcicr & 1) mark_read(PB, d[0x6B]);
  if (pcicr & 2) {
    mark_read(PE, d[0x6C] & 1);
    mark_read(PJ, (uint8_t)(d[0x6C] >> 1));
  }
  if (pcicr & 4) mark_read(PK, d[0x6D]);
}
