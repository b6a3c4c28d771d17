/* An 8N1 receiver that reads a line from the times of its level changes, as a soft UART's
 * pin-change interrupt sees them: a start bit is a falling edge while hunting; each data bit and
 * the stop bit are read at their middles counted from that edge; the hunt for the next start edge
 * resumes at the stop bit's middle. Shared by the firmware's soft UART (hal/runtime/soft_uart.c)
 * and the simulator's decoder of a firmware's soft TX pin (sim/runtime/pin_uart_decoder). */
#ifndef SEAR_DEVICES_UART_EDGES_H
#define SEAR_DEVICES_UART_EDGES_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct uart_edges {
  int level;           /* the line's logic level since the last change (before any inversion: 1 idle) */
  int in_frame;
  uint32_t frame_baud; /* the rate the frame in progress is read at */
  int64_t start_ns;    /* its start edge */
  int next_bit;        /* the next bit to read: 1..8 data, 9 stop */
  uint8_t value;
  int64_t hunt_from_ns; /* a start edge counts from here on */
};

/* Not in a frame, the line at logic `level`, hunting from any time. */
void uart_edges_init(struct uart_edges *r, int level);
/* The line changed to logic `level` at t_ns (changes come in time order; call
 * uart_edges_byte_before(r, t_ns, ...) until it gives nothing first). A falling edge while hunting
 * starts a frame read at `baud`; with baud 0 nothing is read. */
void uart_edges_change(struct uart_edges *r, int level, int64_t t_ns, uint32_t baud);
/* Reads the bits whose middles lie before until_ns, the line holding its level there; returns 1
 * when that completes a byte, with its value and the stop bit's level (0: a framing error), and
 * 0 when no byte completes before until_ns. */
int uart_edges_byte_before(struct uart_edges *r, int64_t until_ns, uint8_t *byte, int *stop_level);

#ifdef __cplusplus
}
#endif
#endif
