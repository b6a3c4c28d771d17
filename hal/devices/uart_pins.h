/* A UART frame played out on a plain pin: the level a device's TX line takes, edge by edge, for
 * an 8N1 byte (start bit low, 8 data bits LSB first, stop bit high) at its baud, each edge at its
 * exact time. For a device wired to a soft UART's RX pin instead of a USART. */
#ifndef SEAR_DEVICES_UART_PINS_H
#define SEAR_DEVICES_UART_PINS_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct uart_pins {
  int inverted;      /* RS-232 polarity at logic levels: idle low, every bit inverted */
  int64_t start_ns;  /* the frame's start edge */
  uint32_t baud;
  uint16_t bits;     /* the frame's 10 logic bits, start first, before any inversion */
  int next_bit;      /* the next bit whose edge is still to come; 10 when the frame is over */
  int level;         /* the line's level now */
};

void uart_pins_init(struct uart_pins *p, int inverted);
/* The line's idle level (HIGH, or LOW when inverted). */
int uart_pins_idle_level(const struct uart_pins *p);
/* A frame carrying `byte` starts at start_ns (a frame still on the line is cut short there);
 * returns the level the line takes at once. */
int uart_pins_start(struct uart_pins *p, uint8_t byte, uint32_t baud, int64_t start_ns);
/* The time of the next level change, INT64_MAX when there is none. */
int64_t uart_pins_next_edge_ns(const struct uart_pins *p);
/* Makes that change; returns the new level. */
int uart_pins_take_edge(struct uart_pins *p);
/* Start of bit j (0 start, 1..8 data, 9 stop, 10 end) from the start edge, rounded to the
 * nearest ns from the start each time, so that errors never accumulate along a frame. */
int64_t uart_pins_bit_ns(int j, uint32_t baud);

#ifdef __cplusplus
}
#endif
#endif
