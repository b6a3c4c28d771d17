/* A UART frame as pin edges (see uart_pins.h). */
#include "devices/uart_pins.h"

int64_t uart_pins_bit_ns(int j, uint32_t baud) {
  return ((int64_t)j * 1000000000 + (int64_t)baud / 2) / (int64_t)baud;
}

void uart_pins_init(struct uart_pins *p, int inverted) {
  p->inverted = inverted != 0;
  p->start_ns = 0;
  p->baud = 0;
  p->bits = 0;
  p->next_bit = 10;
  p->level = uart_pins_idle_level(p);
}

int uart_pins_idle_level(const struct uart_pins *p) { return p->inverted ? 0 : 1; }

static int line_level(const struct uart_pins *p, int j) { return (int)((p->bits >> j) & 1u) ^ p->inverted; }

/* The next bit after `from` whose level differs from the line's now, or 10. */
static int next_change(const struct uart_pins *p, int from) {
  int j = from;
  while (j < 10 && line_level(p, j) == p->level) ++j;
  return j;
}

int uart_pins_start(struct uart_pins *p, uint8_t byte, uint32_t baud, int64_t start_ns) {
  p->start_ns = start_ns;
  p->baud = baud ? baud : 1;
  p->bits = (uint16_t)((uint16_t)byte << 1 | 1u << 9); /* start 0, data LSB first, stop 1 */
  p->level = line_level(p, 0);
  p->next_bit = next_change(p, 1);
  return p->level;
}

int64_t uart_pins_next_edge_ns(const struct uart_pins *p) {
  return p->next_bit < 10 ? p->start_ns + uart_pins_bit_ns(p->next_bit, p->baud) : INT64_MAX;
}

int uart_pins_take_edge(struct uart_pins *p) {
  if (p->next_bit >= 10) return p->level;
  p->level = line_level(p, p->next_bit);
  p->next_bit = next_change(p, p->next_bit + 1);
  return p->level;
}
