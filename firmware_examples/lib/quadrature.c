/* Quadrature decoding: see quadrature.h. */
#include "quadrature.h"

#include <hal/hal.h>

/* Gray-code step from the previous (A<<1 | B) state to the new one, index prev * 4 + now:
 * +1 for 00 -> 10 -> 11 -> 01 -> 00 (A leading: forward), -1 backwards, 0 for no change, and
 * 0 for both channels changing at once, an edge missed, counted in errors. */
static const int8_t quadrature_step[16] = {0, -1, 1, 0, 1, 0, 0, -1, -1, 0, 0, 1, 0, 1, -1, 0};

static uint8_t encoder_state(const struct encoder *e) {
  return (uint8_t)((digital_read(e->pin_a) << 1) | digital_read(e->pin_b));
}

void encoder_begin(struct encoder *e, void (*on_edge)(void)) {
  pin_mode(e->pin_a, INPUT);
  pin_mode(e->pin_b, INPUT);
  e->state = encoder_state(e);
  irq_attach_pin(e->pin_a, IRQ_CHANGE, on_edge);
  irq_attach_pin(e->pin_b, IRQ_CHANGE, on_edge);
}

void encoder_edge(struct encoder *e) {
  const uint8_t now = encoder_state(e);
  const uint8_t index = (uint8_t)((e->state << 2) | now);
  if (now != e->state && quadrature_step[index] == 0) e->errors++;
  e->count += quadrature_step[index];
  e->state = now;
}

int32_t encoder_count(struct encoder *e) {
  irq_disable(); /* four byte reads on the AVR: keep the handler out */
  const int32_t count = e->count;
  irq_enable();
  return count;
}
