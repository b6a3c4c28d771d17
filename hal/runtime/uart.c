/* Serial ports: bytes leave at the baud rate through a 64-byte buffer, each stamped with the end
 * of its stop bit; received bytes become readable (or raise their interrupt) once they are due. */
#include <hal/uart.h>

#include "mcu.h"

static struct mcu_uart *port_of(uint8_t port, const char *call) {
  if (port >= HAL_UART_COUNT) mcu_fatal("%s(%u): the ATmega2560 has UARTs 0..3", call, port);
  return &sear_mcu.uart[port];
}

/* End of the stop bit of byte n (from 1) of the current burst: 10 bit times each (8N1). */
static int64_t burst_end(const struct mcu_uart *u, uint64_t n) {
  return u->anchor_ns + (int64_t)((n * 10ull * 1000000000ull + u->baud / 2) / u->baud);
}

void uart_begin(uint8_t port, uint32_t baud) {
  const int64_t now = mcu_enter(SEAR_CALL_uart_begin);
  struct mcu_uart *u = port_of(port, "uart_begin");
  if (baud < 300 || baud > 2000000) mcu_fatal("uart_begin(%u, %lu): baud must be 300..2000000", port, (unsigned long)baud);
  /* Bytes still on their way out leave at the old rate first, as a driver flushes before it
   * changes the baud register; so the port never holds more than its 66 bytes. The port runs at
   * the new rate from the call's own moment, or once the last of them has left: its TX line
   * idles high from then, so that a logic analyser sees the first start bit fall. */
  if (u->baud && u->last_end_ns > sear_mcu.link->clock_ns) mcu_advance_to(u->last_end_ns);
  const int64_t start = u->baud && u->last_end_ns > now ? u->last_end_ns : now;
  u->baud = baud;
  u->anchor_ns = start;
  u->burst = 0;
  u->last_end_ns = start;
  mcu_emit(SEAR_EVENT_UART_BEGIN, port, baud, start);
}

static void send(uint8_t port, struct mcu_uart *u, uint8_t byte, int64_t now) {
  if (!u->baud) return; /* the transmitter is off until uart_begin(), as on the chip */
  if (u->last_end_ns <= now) {
    u->anchor_ns = now;
    u->burst = 0;
  }
  /* As on the chip: the byte being shifted out, one waiting in the data register and the 64 in
   * the ring. With all of them taken, the write waits for the oldest to leave. */
  if (u->burst >= HAL_UART_BUFFER + 2) {
    const int64_t room_at = burst_end(u, u->burst - HAL_UART_BUFFER - 1);
    if (room_at > sear_mcu.link->clock_ns) mcu_advance_to(room_at);
  }
  /* Every `baud` bytes of a burst take exactly 10 s: moving the anchor by that keeps the
   * arithmetic in burst_end() far from overflow in long runs without changing any time. */
  if (u->burst >= (uint64_t)u->baud + HAL_UART_BUFFER + 2) {
    u->anchor_ns += 10000000000;
    u->burst -= u->baud;
  }
  const int64_t end = burst_end(u, ++u->burst);
  u->last_end_ns = end;
  mcu_emit(SEAR_EVENT_UART_TX, port, byte, end);
  if (sear_mcu.link->uart_loopback_mask & (1u << port)) mcu_uart_arrive(port, byte, end);
  mcu_reschedule();
}

void uart_write(uint8_t port, uint8_t byte) {
  const int64_t now = mcu_enter(SEAR_CALL_uart_write);
  send(port, port_of(port, "uart_write"), byte, now);
}

void uart_print(uint8_t port, const char *text) {
  const int64_t now = mcu_enter(SEAR_CALL_uart_print);
  struct mcu_uart *u = port_of(port, "uart_print");
  for (; *text; ++text) send(port, u, (uint8_t)*text, now > sear_mcu.link->clock_ns ? now : sear_mcu.link->clock_ns);
}

void uart_flush(uint8_t port) {
  mcu_enter(SEAR_CALL_uart_flush);
  struct mcu_uart *u = port_of(port, "uart_flush");
  if (u->baud && u->last_end_ns > sear_mcu.link->clock_ns) mcu_advance_to(u->last_end_ns);
}

uint8_t uart_available(uint8_t port) {
  mcu_enter(SEAR_CALL_uart_available);
  return port_of(port, "uart_available")->rx_count;
}

int16_t uart_read(uint8_t port) {
  mcu_enter(SEAR_CALL_uart_read);
  struct mcu_uart *u = port_of(port, "uart_read");
  if (!u->rx_count) return -1;
  const uint8_t byte = u->rx[u->rx_head];
  u->rx_head = (uint8_t)((u->rx_head + 1) % HAL_UART_BUFFER);
  u->rx_count--;
  return byte;
}

/* Bytes of the current burst still to leave at `now`: those whose stop bit ends later. */
static uint64_t pending(const struct mcu_uart *u, int64_t now) {
  if (!u->baud || u->last_end_ns <= now) return 0;
  const uint64_t gone = (uint64_t)(now - u->anchor_ns) * u->baud / 10000000000ull;
  return u->burst > gone ? u->burst - gone : 0;
}

uint8_t uart_tx_space(uint8_t port) {
  const int64_t now = mcu_enter(SEAR_CALL_uart_tx_space);
  const struct mcu_uart *u = port_of(port, "uart_tx_space");
  /* The shift register and the data register take the first two of a burst. */
  const uint64_t queued = pending(u, now);
  const uint64_t in_ring = queued > 2 ? queued - 2 : 0;
  return (uint8_t)(in_ring >= HAL_UART_BUFFER ? 0 : HAL_UART_BUFFER - in_ring);
}
