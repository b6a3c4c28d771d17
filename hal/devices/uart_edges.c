/* The edge-timed 8N1 receiver (see uart_edges.h). */
#include "devices/uart_edges.h"

void uart_edges_init(struct uart_edges *r, int level) {
  r->level = level;
  r->in_frame = 0;
  r->frame_baud = 0;
  r->start_ns = 0;
  r->next_bit = 1;
  r->value = 0;
  r->hunt_from_ns = INT64_MIN;
}

/* The middle of bit j (0 start, 1..8 data, 9 stop) from the start edge, to the nearest ns. */
static int64_t sample_ns(const struct uart_edges *r, int j) {
  const int64_t baud = (int64_t)r->frame_baud;
  return r->start_ns + ((int64_t)(2 * j + 1) * 1000000000 + baud) / (2 * baud);
}

int uart_edges_byte_before(struct uart_edges *r, int64_t until_ns, uint8_t *byte, int *stop_level) {
  while (r->in_frame && sample_ns(r, r->next_bit) < until_ns) {
    if (r->next_bit <= 8) {
      r->value = (uint8_t)(r->value | r->level << (r->next_bit - 1));
      r->next_bit++;
      continue;
    }
    r->hunt_from_ns = sample_ns(r, 9);
    r->in_frame = 0;
    *byte = r->value;
    *stop_level = r->level;
    return 1;
  }
  return 0;
}

void uart_edges_change(struct uart_edges *r, int level, int64_t t_ns, uint32_t baud) {
  r->level = level;
  if (!r->in_frame && level == 0 && baud && t_ns >= r->hunt_from_ns) {
    r->in_frame = 1;
    r->frame_baud = baud;
    r->start_ns = t_ns;
    r->next_bit = 1;
    r->value = 0;
  }
}
