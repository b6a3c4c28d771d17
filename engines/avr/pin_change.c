/* The pin-change interrupts simavr 1.6's ATmega2560 lacks: it has PCINT0 (PB0..7) only, so a
 * change on PCINT8..23 (PE0, PJ0..6 and A8..A15 = PK0..7) never set PCIF1 or PCIF2 nor ran their
 * vectors. They are added here as the datasheet's External Interrupts chapter has them; and PCIFR
 * is cleared by writing a one to a flag, for all three (simavr writes the one in). */
#include <stdint.h>
#include <string.h>

#include <avr_ioport.h>
#include <sim_avr.h>
#include <sim_interrupts.h>
#include <sim_io.h>
#include <sim_regbit.h>

#include "engine.h"

/* Data addresses (register summary) and vector numbers (table "Reset and Interrupt Vectors"). */
#define PCIFR 0x3B
#define PCICR 0x68
#define PCMSK1 0x6C
#define PCMSK2 0x6D
#define PCINT1_VECTOR 10
#define PCINT2_VECTOR 11

static avr_int_vector_t pcint1 = {.enable = AVR_IO_REGBIT(PCICR, 1),
                                  .raised = AVR_IO_REGBIT(PCIFR, 1),
                                  .vector = PCINT1_VECTOR};
static avr_int_vector_t pcint2 = {.enable = AVR_IO_REGBIT(PCICR, 2),
                                  .raised = AVR_IO_REGBIT(PCIFR, 2),
                                  .vector = PCINT2_VECTOR};
static avr_int_vector_t *pcint0; /* simavr's own, on port B */

/* One watched pin: its bank's vector and mask register, its bit there, its last level. */
struct watched {
  avr_int_vector_t *vector;
  uint16_t pcmsk;
  uint8_t bit;
  uint8_t level;
};
static struct watched pins[16]; /* PE0, PJ0..6, PK0..7 */

/* "Any change on any enabled PCINT pin will cause an interrupt": the flag rises when the pin's
 * PCMSKn bit is set, and the vector runs when PCICR enables it (as simavr does for PCINT0). */
static void on_pin(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  struct watched *w = param;
  const uint8_t level = value != 0;
  if (level == w->level) return;
  w->level = level;
  if (engine.avr->data[w->pcmsk] >> w->bit & 1) avr_raise_interrupt(engine.avr, w->vector);
}

static void on_pcifr_write(avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param) {
  (void)addr;
  (void)param;
  avr_int_vector_t *vectors[3] = {pcint0, &pcint1, &pcint2};
  for (int b = 0; b < 3; ++b) {
    if (!(v >> b & 1) || !vectors[b]) continue;
    avr_clear_interrupt(avr, vectors[b]);
    avr->data[PCIFR] = (uint8_t)(avr->data[PCIFR] & ~(1u << b));
  }
}

static avr_ioport_t *port_named(char name) {
  for (avr_io_t *io = engine.avr->io_port; io; io = io->next)
    if (strcmp(io->kind, "port") == 0 && ((avr_ioport_t *)io)->name == name) return (avr_ioport_t *)io;
  engine_fatal("libsimavr's ATmega2560 has no port %c", name);
  return NULL;
}

static void watch(int i, char port, int port_bit, avr_int_vector_t *vector, uint16_t pcmsk, int bit) {
  avr_irq_t *irq = avr_io_getirq(engine.avr, AVR_IOCTL_IOPORT_GETIRQ(port), IOPORT_IRQ_PIN0 + port_bit);
  if (!irq) engine_fatal("libsimavr's ATmega2560 has no pin P%c%d", port, port_bit);
  pins[i] = (struct watched){vector, pcmsk, (uint8_t)bit, (uint8_t)(irq->value != 0)};
  avr_irq_register_notify(irq, on_pin, &pins[i]);
}

void avr_pin_change_init(void) {
  avr_ioport_t *b = port_named('B');
  pcint0 = b->pcint.vector ? &b->pcint : NULL;
  if (port_named('J')->pcint.vector || port_named('K')->pcint.vector)
    engine_fatal("this libsimavr has PCINT1/PCINT2 of its own: the engine's would run them twice");
  avr_register_vector(engine.avr, &pcint1);
  avr_register_vector(engine.avr, &pcint2);
  /* PCMSK1: PCINT8 is PE0, PCINT9..15 are PJ0..6; PCMSK2: PCINT16..23 are PK0..7. */
  watch(0, 'E', 0, &pcint1, PCMSK1, 0);
  for (int i = 0; i < 7; ++i) watch(1 + i, 'J', i, &pcint1, PCMSK1, i + 1);
  for (int i = 0; i < 8; ++i) watch(8 + i, 'K', i, &pcint2, PCMSK2, i);
  avr_register_io_write(engine.avr, PCIFR, on_pcifr_write, NULL);
}
