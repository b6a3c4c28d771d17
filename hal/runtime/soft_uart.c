/* Soft UARTs (hal/soft_uart.h), built from what the chip does for Arduino's SoftwareSerial: the
 * listener's RX pin raises its pin-change interrupt at each edge, and the handler decodes the
 * frame from the edges' times; a write drives the TX pin at each bit's time with interrupts off.
 *
 * Unlike the Arduino library, whose handler spins through a whole byte from the start bit on,
 * the receiver here reads each edge's exact time (as an input capture would): receiving holds no
 * interrupt off, but an edge is lost as on the chip when a second one comes before the handler
 * ran for the first (one pending flag per pin), as while a write holds interrupts off. */
#include <hal/gpio.h>
#include <hal/soft_uart.h>
#include <stddef.h>

#include "board.h"
#include "devices/uart_edges.h"
#include "devices/uart_pins.h"
#include "mcu.h"

#define NO_LISTENER 0xFF

struct soft_line {
  int open;
  uint8_t rx_pin;
  uint8_t tx_pin;
  uint8_t inverted;
  uint32_t baud;
};

static struct soft_line lines[HAL_SOFT_UART_COUNT];
static uint8_t listener = NO_LISTENER;

/* The listener's receiver: the frame being decoded from its edges, and the ring. */
static struct {
  struct uart_edges line;
  uint8_t ring[HAL_SOFT_UART_BUFFER];
  uint8_t head, tail; /* as the library's: one slot stays empty */
  int overflow;
} rx;

static void check_id(uint8_t id, const char *call) {
  if (id >= HAL_SOFT_UART_COUNT || !lines[id].open)
    mcu_fatal("%s(%u): no soft UART %u is open (soft_uart_begin() gives the id)", call, id, id);
}

static void store(uint8_t byte) {
  const uint8_t next = (uint8_t)((rx.tail + 1) % HAL_SOFT_UART_BUFFER);
  if (next == rx.head) {
    rx.overflow = 1;
    return;
  }
  rx.ring[rx.tail] = byte;
  rx.tail = next;
}

/* Stores every byte whose stop bit's middle lies before until_ns. A stop bit sampled low (a
 * framing error) still gives its byte, as the library does not look. */
static void sample_until(int64_t until_ns) {
  uint8_t byte;
  int stop_level;
  while (uart_edges_byte_before(&rx.line, until_ns, &byte, &stop_level)) store(byte);
}

static void take_edge(int64_t t_ns, int level) {
  sample_until(t_ns);
  uart_edges_change(&rx.line, level, t_ns, lines[listener].baud);
}

static int logic_level(const struct soft_line *l) { return mcu_pin_level(l->rx_pin) ^ l->inverted; }

static void listener_edge(void) {
  const struct soft_line *l = &lines[listener];
  take_edge(sear_mcu.pin_change_ns[l->rx_pin], logic_level(l));
}

/* Bytes whose stop bit has been sampled by now: the line is known up to an edge still waiting
 * for its interrupt, or else up to now. */
static void catch_up(int64_t now) {
  if (listener == NO_LISTENER) return;
  const uint8_t pin = lines[listener].rx_pin;
  sample_until(mcu_pin_pending(pin) ? sear_mcu.pin_change_ns[pin] : now + 1);
}

static void stop_listening(void) {
  if (listener == NO_LISTENER) return;
  const uint8_t pin = lines[listener].rx_pin;
  if (sear_mcu.pin_handler[pin] == listener_edge) {
    sear_mcu.pin_handler[pin] = NULL;
    mcu_set_pin_pending(pin, 0);
  }
  listener = NO_LISTENER;
}

static void start_listening(uint8_t id) {
  const struct soft_line *l = &lines[id];
  listener = id;
  uart_edges_init(&rx.line, logic_level(l));
  rx.head = rx.tail = 0;
  sear_mcu.pin_handler[l->rx_pin] = listener_edge;
  sear_mcu.pin_edges[l->rx_pin] = IRQ_CHANGE;
  mcu_set_pin_pending(l->rx_pin, 0);
  sear_mcu.link->usage.pin_read[l->rx_pin] = 1;
  mcu_watch_idle_loops();
  mcu_reschedule();
}

uint8_t soft_uart_begin(uint8_t rx_pin, uint8_t tx_pin, uint32_t baud, uint8_t inverted) {
  mcu_enter(SEAR_CALL_soft_uart_begin);
  mcu_check_pin(rx_pin, "soft_uart_begin");
  mcu_check_pin(tx_pin, "soft_uart_begin");
  if (!board_has_pin_change(rx_pin))
    mcu_fatal("soft_uart_begin(%u, %u, %lu): RX pin %u has no pin-change interrupt; a soft UART receives on "
              "10..15, 50..53 and A8..A15 (62..69) of the ATmega2560 board",
              rx_pin, tx_pin, (unsigned long)baud, rx_pin);
  if (rx_pin == tx_pin) mcu_fatal("soft_uart_begin(%u, %u, %lu): RX and TX on one pin", rx_pin, tx_pin, (unsigned long)baud);
  if (baud < 300 || baud > 115200)
    mcu_fatal("soft_uart_begin(%u, %u, %lu): the baud must be 300..115200", rx_pin, tx_pin, (unsigned long)baud);
  uint8_t id = HAL_SOFT_UART_COUNT;
  for (uint8_t i = 0; i < HAL_SOFT_UART_COUNT; ++i) {
    if (lines[i].open && (lines[i].rx_pin == rx_pin || lines[i].tx_pin == tx_pin)) {
      if (lines[i].rx_pin != rx_pin || lines[i].tx_pin != tx_pin)
        mcu_fatal("soft_uart_begin(%u, %u, %lu): soft UART %u already has pin %u", rx_pin, tx_pin, (unsigned long)baud,
                  i, lines[i].rx_pin == rx_pin ? rx_pin : tx_pin);
      id = i; /* begun again: the same line at the new rate */
      break;
    }
  }
  for (uint8_t i = 0; id == HAL_SOFT_UART_COUNT && i < HAL_SOFT_UART_COUNT; ++i)
    if (!lines[i].open) id = i;
  if (id == HAL_SOFT_UART_COUNT)
    mcu_fatal("soft_uart_begin(%u, %u, %lu): %d soft UARTs are open already", rx_pin, tx_pin, (unsigned long)baud,
              HAL_SOFT_UART_COUNT);
  if (listener == id) stop_listening();
  lines[id] = (struct soft_line){1, rx_pin, tx_pin, inverted ? 1 : 0, baud};
  /* TX idles at the stop bit's level before it becomes an output, so no false start bit goes out;
   * RX keeps its pull-up on for normal polarity, as the library sets it. */
  digital_write(tx_pin, inverted ? LOW : HIGH);
  pin_mode(tx_pin, OUTPUT);
  pin_mode(rx_pin, inverted ? INPUT : INPUT_PULLUP);
  stop_listening();
  start_listening(id);
  return id;
}

void soft_uart_end(uint8_t id) {
  mcu_enter(SEAR_CALL_soft_uart_end);
  check_id(id, "soft_uart_end");
  if (listener == id) stop_listening();
  lines[id].open = 0;
}

uint8_t soft_uart_listen(uint8_t id) {
  mcu_enter(SEAR_CALL_soft_uart_listen);
  check_id(id, "soft_uart_listen");
  if (listener == id) return 0;
  stop_listening();
  start_listening(id);
  return 1;
}

uint8_t soft_uart_stop_listening(uint8_t id) {
  mcu_enter(SEAR_CALL_soft_uart_stop_listening);
  check_id(id, "soft_uart_stop_listening");
  if (listener != id) return 0;
  stop_listening();
  return 1;
}

uint8_t soft_uart_is_listening(uint8_t id) {
  mcu_enter(SEAR_CALL_soft_uart_is_listening);
  check_id(id, "soft_uart_is_listening");
  return listener == id;
}

uint8_t soft_uart_available(uint8_t id) {
  const int64_t now = mcu_enter(SEAR_CALL_soft_uart_available);
  check_id(id, "soft_uart_available");
  if (listener != id) return 0;
  catch_up(now);
  return (uint8_t)((rx.tail + HAL_SOFT_UART_BUFFER - rx.head) % HAL_SOFT_UART_BUFFER);
}

static int16_t next_byte(uint8_t id, int64_t now, int take) {
  if (listener != id) return -1;
  catch_up(now);
  if (rx.head == rx.tail) return -1;
  const uint8_t byte = rx.ring[rx.head];
  if (take) rx.head = (uint8_t)((rx.head + 1) % HAL_SOFT_UART_BUFFER);
  return byte;
}

int16_t soft_uart_read(uint8_t id) {
  const int64_t now = mcu_enter(SEAR_CALL_soft_uart_read);
  check_id(id, "soft_uart_read");
  return next_byte(id, now, 1);
}

int16_t soft_uart_peek(uint8_t id) {
  const int64_t now = mcu_enter(SEAR_CALL_soft_uart_peek);
  check_id(id, "soft_uart_peek");
  return next_byte(id, now, 0);
}

/* As the library's write(): interrupts off from the start bit's edge until the stop bit's, whose
 * time then passes with them on again (as it was before). */
void soft_uart_write(uint8_t id, uint8_t byte) {
  mcu_enter(SEAR_CALL_soft_uart_write);
  check_id(id, "soft_uart_write");
  /* The start edge once the call's cost has passed: it then falls in the quantum the clock is in
   * (the call may have taken it past the last one's end). */
  const int64_t now = sear_mcu.link->clock_ns;
  const struct soft_line *l = &lines[id];
  const int was_enabled = sear_mcu.irq_enabled;
  sear_mcu.irq_enabled = 0;
  mcu_reschedule();
  const uint16_t bits = (uint16_t)((uint16_t)byte << 1 | 1u << 9);
  for (int j = 0; j < 10; ++j) {
    const int64_t t = now + uart_pins_bit_ns(j, l->baud);
    mcu_advance_to(t);
    mcu_drive_latch(l->tx_pin, (uint8_t)(((bits >> j) & 1u) ^ l->inverted), t);
  }
  sear_mcu.irq_enabled = was_enabled;
  mcu_reschedule();
  mcu_advance_to(now + uart_pins_bit_ns(10, l->baud));
}

uint8_t soft_uart_overflow(uint8_t id) {
  mcu_enter(SEAR_CALL_soft_uart_overflow);
  check_id(id, "soft_uart_overflow");
  const int was = rx.overflow;
  rx.overflow = 0;
  return (uint8_t)was;
}
