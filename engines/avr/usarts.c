/* The four USARTs: bytes the firmware writes to UDRn leave at the baud its UBRRn gives and are
 * stamped with their stop bit's end; bytes from the simulator enter at theirs, held as the chip
 * holds them (simavr's own FIFO holds 64): two in the receive buffer and a third waiting in the
 * shift register; a fourth unread byte is an overrun (DORn), lost as on the chip. */
#include <stdint.h>
#include <string.h>

#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include <sim_interrupts.h>
#include <sim_io.h>

#include "engine.h"

#define ARRIVALS 8192 /* the link's rx[] holds at most this many per quantum */

/* UCSRnA, UCSRnB, UCSRnC and UBRRnL data addresses (ATmega2560 register summary). */
static const uint16_t ucsra[SEAR_LINK_UARTS] = {0xC0, 0xC8, 0xD0, 0x130};
#define UCSRB(n) (uint16_t)(ucsra[n] + 1)
#define UCSRC(n) (uint16_t)(ucsra[n] + 2)
#define UBRRL(n) (uint16_t)(ucsra[n] + 4)
#define U2X 0x02
#define DOR 0x08
#define TXEN 0x08
#define RXEN 0x10

static struct {
  avr_uart_t *uart;
  avr_irq_t *irq;
  uint32_t baud_told;  /* the rate last sent as UART_BEGIN */
  int64_t line_free_ns; /* when the transmitter's last stop bit ends */
  uint32_t overruns;
  avr_io_read_t udr_read; /* simavr's own read of UDRn, which ours wraps */
  void *udr_param;
} ports[SEAR_LINK_UARTS];

/* The chip's receive buffer, two frames, and its shift register, which holds a third until the
 * buffer has room (the datasheet's USART chapter: an overrun needs both full and a new start bit). */
#define RX_HELD 3

static struct {
  int64_t time_ns;
  uint8_t port, byte;
} arrivals[ARRIVALS];
static uint32_t arrival_head, arrival_count;

/* The rate the divider makes (datasheet table 22-1): f / (16 (UBRR + 1)), or / 8 with U2X. */
static double baud_of(int n) {
  const uint8_t *d = engine.avr->data;
  const uint32_t ubrr = (uint32_t)(d[UBRRL(n)] | (d[UBRRL(n) + 1] & 0x0F) << 8);
  return (double)engine.clock_hz / ((d[ucsra[n]] & U2X ? 8.0 : 16.0) * (ubrr + 1));
}

/* Start, data, parity and stop bits of one frame (UCSRnC, UCSZn2). */
static int frame_bits(int n) {
  const uint8_t *d = engine.avr->data;
  const int ucsz = (d[UCSRC(n)] >> 1 & 3) | (d[UCSRB(n)] & 0x04);
  const int data_bits = ucsz <= 3 ? 5 + ucsz : 9;
  const int parity = (d[UCSRC(n)] >> 4 & 3) != 0;
  const int stop = 1 + (d[UCSRC(n)] >> 3 & 1);
  return 1 + data_bits + parity + stop;
}

static int64_t frame_ns(int n) { return (int64_t)((double)frame_bits(n) * 1e9 / baud_of(n) + 0.5); }

/* simavr 1.6 counts a parity bit in every frame (11 bits for 8N1), which paces its UDRE, TXC and
 * RXC flags 10 % slow: its frame is set to the chip's, in cycles. */
static void fix_frame(int n) {
  const uint8_t *d = engine.avr->data;
  const uint32_t ubrr = (uint32_t)(d[UBRRL(n)] | (d[UBRRL(n) + 1] & 0x0F) << 8);
  ports[n].uart->cycles_per_byte = (avr_cycle_count_t)frame_bits(n) * (ubrr + 1) * (d[ucsra[n]] & U2X ? 8u : 16u);
}

/* simavr starts its receive pump (which raises RXC) one frame after a byte comes in; the byte
 * comes in here at its stop bit's end, when the chip raises RXC, so the pump is started at once.
 * The pump is the timer the input just registered for this USART. */
static avr_cycle_timer_t rx_pump;

static int has_timer(avr_cycle_timer_t fn, const void *param) {
  for (avr_cycle_timer_slot_p s = engine.avr->cycle_timers.timer; s; s = s->next)
    if (s->timer == fn && s->param == param) return 1;
  return 0;
}

static void give_byte(int n, uint8_t byte) {
  avr_uart_t *u = ports[n].uart;
  avr_cycle_timer_t before[MAX_CYCLE_TIMERS];
  int count = 0;
  for (avr_cycle_timer_slot_p s = engine.avr->cycle_timers.timer; s && count < MAX_CYCLE_TIMERS; s = s->next)
    if (s->param == u) before[count++] = s->timer;
  avr_raise_irq(ports[n].irq, byte);
  if (!rx_pump) {
    for (avr_cycle_timer_slot_p s = engine.avr->cycle_timers.timer; s && !rx_pump; s = s->next) {
      if (s->param != u) continue;
      int known = 0;
      for (int i = 0; i < count; ++i) known |= before[i] == s->timer;
      if (!known) rx_pump = s->timer;
    }
  }
  if (rx_pump && has_timer(rx_pump, u)) {
    avr_cycle_timer_cancel(engine.avr, rx_pump, u);
    avr_cycle_timer_register(engine.avr, 1, rx_pump, u);
  }
}

/* The port's rate reaches the simulator once it is enabled, and again whenever it changes. */
static void tell_baud(int n, int64_t now) {
  const uint8_t b = engine.avr->data[UCSRB(n)];
  if (!(b & (TXEN | RXEN))) return;
  const uint32_t baud = (uint32_t)(baud_of(n) + 0.5);
  if (baud == ports[n].baud_told || baud < 300 || baud > 2000000) return;
  ports[n].baud_told = baud;
  engine_emit(SEAR_EVENT_UART_BEGIN, (uint8_t)n, baud, now);
}

static void arrive(int64_t time_ns, uint8_t port, uint8_t byte) {
  if (arrival_count == ARRIVALS) {
    ports[port].overruns++;
    return;
  }
  const uint32_t at = (arrival_head + arrival_count++) % ARRIVALS;
  arrivals[at].time_ns = time_ns;
  arrivals[at].port = port;
  arrivals[at].byte = byte;
}

static uint32_t fifo_fill(const avr_uart_t *u) { return (uint32_t)((u->input.write - u->input.read) & 63u); }

/* DORn "is valid until the receive buffer (UDRn) is read" (UCSRnA in the datasheet): simavr never
 * clears it, so a read of UDRn does, after simavr's own read has taken the byte. The chip keeps the
 * flag with the frame it follows; here it goes with the first read after the loss.
 * RXCn "is set when there are unread data in the receive buffer": simavr 1.6 clears it on a read
 * that comes sooner than one frame after the last (it will not let a byte be read "faster than the
 * baud rate") and raises it again a frame later, so a firmware that was held up never catches up:
 * the bytes waiting stay waiting, and the next delay overruns. The flag, and the interrupt, stay
 * set while a byte waits, as on the chip, and an RX ISR takes the backlog back to back. */
static uint8_t udr_read(avr_t *avr, avr_io_addr_t addr, void *param) {
  const int n = (int)(intptr_t)param;
  const uint8_t byte = ports[n].udr_read ? ports[n].udr_read(avr, addr, ports[n].udr_param) : avr->data[addr];
  avr->data[ucsra[n]] = (uint8_t)(avr->data[ucsra[n]] & ~DOR);
  avr_uart_t *u = ports[n].uart;
  if (u && fifo_fill(u) && (avr->data[UCSRB(n)] & RXEN)) avr_raise_interrupt(avr, &u->rxc);
  return byte;
}

uint32_t avr_usart_overruns(int n) { return n >= 0 && n < SEAR_LINK_UARTS ? ports[n].overruns : 0; }

static void on_tx(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  const int n = (int)(intptr_t)param;
  const int64_t now = engine_now_ns();
  tell_baud(n, now);
  fix_frame(n);
  /* The shift register takes the byte at once if it is idle, else when the one before is out. */
  const int64_t start = ports[n].line_free_ns > now ? ports[n].line_free_ns : now;
  const int64_t end = start + frame_ns(n);
  ports[n].line_free_ns = end;
  engine_emit(SEAR_EVENT_UART_TX, (uint8_t)n, value & 0xFF, end);
  if (engine.link->uart_loopback_mask >> n & 1) arrive(end, (uint8_t)n, (uint8_t)value);
}

void avr_usarts_init(void) {
  memset(ports, 0, sizeof ports);
  for (avr_io_t *io = engine.avr->io_port; io; io = io->next) {
    if (strcmp(io->kind, "uart") != 0) continue;
    avr_uart_t *u = (avr_uart_t *)io;
    const int n = u->name - '0';
    if (n < 0 || n >= SEAR_LINK_UARTS) continue;
    ports[n].uart = u;
    /* No host sleeps while the firmware polls UCSRnA, no copy of the bytes on stdout. */
    uint32_t flags = 0;
    avr_ioctl(engine.avr, AVR_IOCTL_UART_SET_FLAGS(u->name), &flags);
    ports[n].irq = avr_io_getirq(engine.avr, AVR_IOCTL_UART_GETIRQ(u->name), UART_IRQ_INPUT);
    avr_irq_register_notify(avr_io_getirq(engine.avr, AVR_IOCTL_UART_GETIRQ(u->name), UART_IRQ_OUTPUT), on_tx,
                            (void *)(intptr_t)n);
    /* simavr refuses a second reader of an address, so ours takes its place and calls it. */
    const avr_io_addr_t udr = AVR_DATA_TO_IO(u->r_udr);
    ports[n].udr_read = engine.avr->io[udr].r.c;
    ports[n].udr_param = engine.avr->io[udr].r.param;
    engine.avr->io[udr].r.c = udr_read;
    engine.avr->io[udr].r.param = (void *)(intptr_t)n;
  }
  for (int n = 0; n < SEAR_LINK_UARTS; ++n)
    if (!ports[n].uart) engine_fatal("libsimavr's ATmega2560 has no USART%d", n);
}

void avr_usarts_take_quantum(void) {
  const struct sear_link *link = engine.link;
  const uint32_t count = link->rx_count < SEAR_LINK_MAX_RX ? link->rx_count : SEAR_LINK_MAX_RX;
  for (uint32_t i = 0; i < count; ++i)
    if (link->rx[i].port < SEAR_LINK_UARTS) arrive(link->rx[i].time_ns, link->rx[i].port, link->rx[i].byte);
  /* Ports a firmware set up without sending yet still tell their rate. */
  for (int n = 0; n < SEAR_LINK_UARTS; ++n) tell_baud(n, engine.turn_start_ns);
}

int64_t avr_usarts_next_ns(void) { return arrival_count ? arrivals[arrival_head].time_ns : INT64_MAX; }

void avr_usarts_run_due(int64_t now_ns) {
  while (arrival_count && arrivals[arrival_head].time_ns <= now_ns) {
    const int n = arrivals[arrival_head].port;
    const uint8_t byte = arrivals[arrival_head].byte;
    const int64_t t = arrivals[arrival_head].time_ns;
    arrival_head = (arrival_head + 1) % ARRIVALS;
    arrival_count--;
    uint8_t *d = engine.avr->data;
    if (!(d[UCSRB(n)] & RXEN)) continue; /* the receiver is off, as on the chip */
    tell_baud(n, engine_now_ns());
    engine_emit(SEAR_EVENT_UART_RX, (uint8_t)n, byte, t < engine.turn_start_ns ? engine.turn_start_ns : t);
    if (fifo_fill(ports[n].uart) >= RX_HELD) {
      d[ucsra[n]] |= DOR;
      ports[n].overruns++;
      continue;
    }
    fix_frame(n);
    give_byte(n, byte);
  }
}
