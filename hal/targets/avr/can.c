/* hal/can.h on a real board: an MCP2515 CAN controller on the SPI bus (the CAN-BUS shield of an
 * Arduino Mega), driven register by register through the HAL's own spi_*, digital_* and
 * irq_attach_pin, so the same file also builds natively for its host-side test. Register names
 * and page numbers are those of the MCP2515 datasheet, Microchip DS20001801.
 *
 * Where the chip cannot be exactly what hal/can.h (and the simulator) describe:
 * - Overruns: EFLG holds a flag, not a count, so frames lost in one spell of full buffers count once.
 * - Filters 2-5 put a frame straight into RXB1: with RXB1 full it is lost even if RXB0 is free; and
 *   two such frames arriving between two looks at the chip cannot be told apart in age.
 * - One mask serves standard and extended filters alike: a group with an extended filter compares
 *   its standard filters against mask bits 28..18.
 * - Keeping the send order oldest first (by TXP, never rewriting a pending buffer's priority) may
 *   refuse a frame with a buffer free, at most once per 12 accepted, while the queue never drains.
 * - Changing filters takes the controller off the bus for a moment (configuration mode).
 * - While can_attach_rx is active, other SPI drivers must hold interrupts off around their own
 *   transactions, or the CAN interrupt cuts into them. */
#include <hal/can.h>
#include <hal/gpio.h>
#include <hal/irq.h>
#include <hal/spi.h>
#include <hal/time.h>

#include "mcp2515.h"

#include <stddef.h>
#include <string.h>

#if defined(__AVR__)
#include <avr/io.h> /* SREG: see lock() */
#endif

/* The crystal on the shield: 16 MHz on the usual Arduino CAN shields, 8 MHz on the cheap
 * blue modules. */
#ifndef SEAR_MCP2515_OSC_HZ
#define SEAR_MCP2515_OSC_HZ 16000000UL
#endif
#ifndef SEAR_MCP2515_CS_PIN
#define SEAR_MCP2515_CS_PIN 10
#endif
#ifndef SEAR_MCP2515_INT_PIN
#define SEAR_MCP2515_INT_PIN 2
#endif

/* The MCP2515 takes up to 10 MHz; spi_begin rounds this down to 16 MHz / 2 on a Mega. */
#define SPI_CLOCK_HZ 8000000UL
#define SPI_MODE 0

#define TX_KEYS 12u /* TXP 0..3 times buffer 0..2: the order the controller sends pending frames in */
#define ID_STD_MASK 0x7FFUL
#define ID_EXT_MASK 0x1FFFFFFFUL

static void (*volatile rx_handler)(void);
static uint8_t rx_armed;   /* CANINTE's RXnIE: buffers whose next frame is still to be told */
static uint8_t rx_seen;    /* RXnIF as last seen, to tell which of two full buffers is older */
static uint8_t rx_older;   /* the buffer to read first when both are full */
static uint8_t tx_key[CAN_TX_BUFFERS];
static uint16_t overruns;
static uint32_t bitrate_now;

/* Acceptance as can.h states it, kept here because the controller takes new filters only in
 * configuration mode and each mask's register layout depends on its filters (apply_filters). */
static uint8_t filtering;
static uint32_t mask_bits[2];
static uint32_t filter_id[CAN_FILTERS];
static uint8_t filter_ext[CAN_FILTERS];

/* ---- Mutual exclusion with the receive interrupt ----
 * The interrupt talks to the controller over the same SPI bus, so a transaction in the main
 * program must not be cut in two by it. The HAL's irq_enable() cannot restore the state that
 * came before (a can_send from a timer handler would turn interrupts on inside that handler),
 * so the AVR build saves and restores SREG as avr-libc's ATOMIC_RESTORESTATE does; elsewhere
 * (the host test) the interrupt is known to be running by a flag the handler sets. */
#if defined(__AVR__)
typedef uint8_t lock_state;
static lock_state lock(void) {
  lock_state state = SREG;
  irq_disable();
  return state;
}
static void unlock(lock_state state) { SREG = state; }
#else
static volatile uint8_t in_interrupt;
typedef uint8_t lock_state;
static lock_state lock(void) {
  if (in_interrupt) return 0;
  irq_disable();
  return 1;
}
static void unlock(lock_state state) {
  if (state) irq_enable();
}
#endif

/* ---- SPI instructions (datasheet section 12); callers hold the lock ---- */

static void select_chip(void) {
  /* Each time: another SPI device of the firmware may have set its own mode and clock. */
  spi_begin(SPI_MODE, SPI_CLOCK_HZ);
  digital_write(SEAR_MCP2515_CS_PIN, LOW);
}

static void release_chip(void) { digital_write(SEAR_MCP2515_CS_PIN, HIGH); }

static void read_regs(uint8_t address, uint8_t *out, uint8_t count) {
  select_chip();
  spi_transfer(MCP_READ);
  spi_transfer(address);
  for (uint8_t i = 0; i < count; i++) out[i] = spi_transfer(0);
  release_chip();
}

static uint8_t read_reg(uint8_t address) {
  uint8_t value;
  read_regs(address, &value, 1);
  return value;
}

static void write_regs(uint8_t address, const uint8_t *bytes, uint8_t count) {
  select_chip();
  spi_transfer(MCP_WRITE);
  spi_transfer(address);
  for (uint8_t i = 0; i < count; i++) spi_transfer(bytes[i]);
  release_chip();
}

static void write_reg(uint8_t address, uint8_t value) { write_regs(address, &value, 1); }

static void bit_modify(uint8_t address, uint8_t mask, uint8_t value) {
  select_chip();
  spi_transfer(MCP_BIT_MODIFY);
  spi_transfer(address);
  spi_transfer(mask);
  spi_transfer(value);
  release_chip();
}

static uint8_t read_status(void) {
  select_chip();
  spi_transfer(MCP_READ_STATUS);
  uint8_t status = spi_transfer(0);
  release_chip();
  return status;
}

static uint8_t locked_read(uint8_t address) {
  lock_state state = lock();
  uint8_t value = read_reg(address);
  unlock(state);
  return value;
}

static void locked_bit_modify(uint8_t address, uint8_t mask, uint8_t value) {
  lock_state state = lock();
  bit_modify(address, mask, value);
  unlock(state);
}

/* ---- Bit timing (datasheet section 5) ---- */

int8_t mcp2515_bit_timing(uint32_t osc_hz, uint32_t bitrate, uint8_t cnf[3]) {
  if (bitrate == 0 || bitrate > 1000000UL || osc_hz % (2u * bitrate) != 0) return -1;
  /* TQ = 2 (BRP + 1) / Fosc and a bit lasts N quanta, so Fosc / (2 bitrate) = (BRP + 1) N. */
  const uint32_t quanta = osc_hz / (2u * bitrate);
  /* N is 1 (sync) + PRSEG + PHSEG1 + PHSEG2 quanta, PRSEG and PHSEG1 at most 8 each. A sample
   * point at or before 87.5 % (CiA 301's) needs PHSEG2 >= N / 8, so N <= 17 + ceil(N / 8):
   * 20 at most. The most quanta that divide evenly place the sample point the most finely. */
  for (uint8_t n = 20; n >= 8; n--) {
    if (quanta % n != 0 || quanta / n > 64) continue;
    /* Rounded up so the sample point stays at or below 87.5 %, and at least 2 quanta: the
     * information processing time, and more than SJW (1) as section 5.3 asks. */
    uint8_t phseg2 = (uint8_t)((n + 7u) / 8u);
    if (phseg2 < 2) phseg2 = 2;
    /* PRSEG + PHSEG1 >= PHSEG2 (section 5.3) holds since n >= 8 leaves them 5 or more. */
    const uint8_t before = (uint8_t)(n - 1u - phseg2);
    const uint8_t prseg = (uint8_t)(before / 2u);
    const uint8_t phseg1 = (uint8_t)(before - prseg);
    cnf[0] = (uint8_t)(quanta / n - 1u); /* SJW = 1 TQ (bits 7..6 = 00), BRP */
    cnf[1] = (uint8_t)(MCP_CNF2_BTLMODE | ((phseg1 - 1u) << 3) | (prseg - 1u)); /* SAM = 0 */
    cnf[2] = (uint8_t)(phseg2 - 1u);
    return 0;
  }
  return -1;
}

/* ---- Modes (datasheet section 10) ---- */

static int8_t wait_mode(uint8_t mode, uint32_t limit_us) {
  const uint32_t start = micros();
  while ((locked_read(MCP_CANSTAT) & MCP_MODE_MASK) != mode) {
    if ((uint32_t)(micros() - start) > limit_us) return -1;
  }
  return 0;
}

/* The longest three frames can take (an extended 8-byte frame is at most 160 bits with
 * stuffing), plus a millisecond for the SPI round trips. */
static uint32_t three_frames_us(void) {
  return (uint32_t)(bitrate_now ? 3UL * 160UL * 1000000UL / bitrate_now + 1000UL : 1000UL);
}

/* Configuration mode waits for pending frames to go out (section 10.1); when the bus does not
 * take them (no other node acknowledging), they are aborted rather than wait for ever. */
static int8_t enter_config(void) {
  locked_bit_modify(MCP_CANCTRL, MCP_MODE_MASK, MCP_MODE_CONFIG);
  if (wait_mode(MCP_MODE_CONFIG, three_frames_us()) == 0) return 0;
  locked_bit_modify(MCP_CANCTRL, MCP_CANCTRL_ABAT, MCP_CANCTRL_ABAT);
  const int8_t result = wait_mode(MCP_MODE_CONFIG, three_frames_us());
  locked_bit_modify(MCP_CANCTRL, MCP_CANCTRL_ABAT, 0);
  return result;
}

static int8_t enter_normal(void) {
  locked_bit_modify(MCP_CANCTRL, MCP_MODE_MASK, MCP_MODE_NORMAL);
  return wait_mode(MCP_MODE_NORMAL, three_frames_us());
}

/* ---- Acceptance filters (datasheet section 4.5) ---- */

/* An identifier as the four SIDH, SIDL, EID8, EID0 bytes: an 11-bit one fills SID10..0 only,
 * a 29-bit one SID10..0 with its bits 28..18 and EID17..0 with the rest. */
static void id_bytes(uint32_t id, uint8_t extended, uint8_t out[4]) {
  if (extended) {
    id &= ID_EXT_MASK;
    out[0] = (uint8_t)(id >> 21);
    out[1] = (uint8_t)((((id >> 18) & 7u) << 5) | MCP_SIDL_EXIDE | ((id >> 16) & 3u));
    out[2] = (uint8_t)(id >> 8);
    out[3] = (uint8_t)id;
  } else {
    id &= ID_STD_MASK;
    out[0] = (uint8_t)(id >> 3);
    out[1] = (uint8_t)((id & 7u) << 5);
    out[2] = 0;
    out[3] = 0;
  }
}

/* A mask register has one layout for both kinds of frame, so it takes that of its filters:
 * 29-bit as soon as one of them is extended, else 11-bit with EID15..0 left 0 (the controller
 * would otherwise compare them with a standard frame's first two data bytes). A group mixing
 * both kinds therefore compares standard frames with mask bits 28..18: the hardware's limit. */
static void apply_filters(void) {
  if (enter_config() != 0) return;
  lock_state state = lock();
  uint8_t group_ext[2] = {0, 0};
  for (uint8_t f = 0; f < CAN_FILTERS; f++) {
    uint8_t bytes[4];
    id_bytes(filter_id[f], filter_ext[f], bytes);
    write_regs(MCP_RXF_SIDH(f), bytes, 4);
    group_ext[f < 2 ? 0 : 1] |= filter_ext[f];
  }
  for (uint8_t m = 0; m < 2; m++) {
    uint8_t bytes[4];
    id_bytes(mask_bits[m], group_ext[m], bytes);
    bytes[1] &= (uint8_t)~MCP_SIDL_EXIDE; /* not a bit of RXMnSIDL */
    write_regs(MCP_RXM_SIDH(m), bytes, 4);
  }
  const uint8_t rxm = filtering ? MCP_RXM_FILTERED : MCP_RXM_ANY;
  bit_modify(MCP_RXB0CTRL, MCP_RXM_MASK | MCP_RXB0_BUKT, (uint8_t)(rxm | MCP_RXB0_BUKT));
  bit_modify(MCP_RXB1CTRL, MCP_RXM_MASK, rxm);
  unlock(state);
  enter_normal();
}

void can_set_mask(uint8_t mask, uint32_t bits) {
  if (mask > 1) return;
  mask_bits[mask] = bits;
  filtering = 1;
  apply_filters();
}

void can_set_filter(uint8_t filter, uint32_t id, uint8_t extended) {
  if (filter >= CAN_FILTERS) return;
  filter_id[filter] = id;
  filter_ext[filter] = extended ? 1 : 0;
  filtering = 1;
  apply_filters();
}

/* ---- Reception (datasheet section 4) ---- */

/* The controller keeps no arrival order: with BUKT a frame goes to RXB0 when it is empty and
 * rolls over to RXB1 otherwise, so of two full buffers RXB1 is the older exactly when it was
 * already full when RXB0 was last emptied. Every look at RXnIF notes which flag is new. A frame
 * that filters 2..5 put straight into RXB1 breaks that rule; when both such arrive between two
 * looks the order is unknowable and RXB0 goes first. */
static void note_arrivals(uint8_t flags) {
  const uint8_t fresh = (uint8_t)(flags & ~rx_seen);
  if (fresh == MCP_INT_RX0 && (rx_seen & MCP_INT_RX1))
    rx_older = 1;
  else if (fresh == MCP_INT_RX1 && (rx_seen & MCP_INT_RX0))
    rx_older = 0;
  else if (fresh)
    rx_older = (fresh & MCP_INT_RX0) ? 0 : 1;
  rx_seen = flags;
}

static uint8_t rx_flags(void) {
  const uint8_t flags = (uint8_t)(read_status() & (MCP_STATUS_RX0IF | MCP_STATUS_RX1IF));
  note_arrivals(flags);
  return flags;
}

/* EFLG's overflow bits are flags, not counts: frames lost during one spell of both buffers
 * full count once. */
static void count_overruns(void) {
  const uint8_t eflg = read_reg(MCP_EFLG);
  if (eflg & (MCP_EFLG_RX0OVR | MCP_EFLG_RX1OVR)) {
    if (overruns != 0xFFFFu) overruns++;
    bit_modify(MCP_EFLG, MCP_EFLG_RX0OVR | MCP_EFLG_RX1OVR, 0);
  }
}

uint8_t can_available(void) {
  lock_state state = lock();
  const uint8_t flags = rx_flags();
  unlock(state);
  return (uint8_t)((flags & 1u) + ((flags >> 1) & 1u));
}

int8_t can_receive(struct can_frame *frame) {
  lock_state state = lock();
  const uint8_t flags = rx_flags();
  if (!flags) {
    unlock(state);
    return 0;
  }
  const uint8_t buffer = flags == (MCP_INT_RX0 | MCP_INT_RX1) ? rx_older : (flags == MCP_INT_RX0 ? 0 : 1);
  const uint8_t bit = (uint8_t)(1u << buffer);

  /* READ RX BUFFER: SIDH, SIDL, EID8, EID0, DLC, D0..D7; raising CS clears RXnIF. */
  uint8_t head[5];
  select_chip();
  spi_transfer(buffer ? MCP_READ_RX1 : MCP_READ_RX0);
  for (uint8_t i = 0; i < 5; i++) head[i] = spi_transfer(0);
  memset(frame, 0, sizeof *frame);
  frame->extended = (head[1] & MCP_SIDL_EXIDE) ? 1 : 0;
  if (frame->extended) {
    frame->id = ((uint32_t)head[0] << 21) | ((uint32_t)(head[1] >> 5) << 18) | ((uint32_t)(head[1] & 3u) << 16) |
                ((uint32_t)head[2] << 8) | head[3];
    frame->remote = (head[4] & MCP_DLC_RTR) ? 1 : 0;
  } else {
    frame->id = ((uint32_t)head[0] << 3) | (uint32_t)(head[1] >> 5);
    frame->remote = (head[1] & MCP_SIDL_SRR) ? 1 : 0;
  }
  uint8_t dlc = (uint8_t)(head[4] & MCP_DLC_MASK);
  frame->dlc = dlc > 8 ? 8 : dlc; /* a DLC of 9..15 still carries 8 bytes */
  if (!frame->remote) {
    for (uint8_t i = 0; i < frame->dlc; i++) frame->data[i] = spi_transfer(0);
  }
  release_chip();
  rx_seen &= (uint8_t)~bit;

  /* A frame can only be lost while both buffers are full: look then. */
  if (flags == (MCP_INT_RX0 | MCP_INT_RX1)) count_overruns();
  /* This buffer's next frame is to be told again (see on_interrupt). */
  if (rx_handler && !(rx_armed & bit)) {
    rx_armed |= bit;
    bit_modify(MCP_CANINTE, bit, bit);
  }
  unlock(state);
  return 1;
}

/* INT stays low while any enabled flag is set, and only its falling edge interrupts, so each
 * buffer's interrupt is disabled once told and enabled again when can_receive empties it: INT
 * rises and the next frame makes a new edge, whether or not the handler read the frame. */
static void on_interrupt(void) {
#if !defined(__AVR__)
  in_interrupt = 1;
#endif
  for (;;) {
    const uint8_t fresh = (uint8_t)(rx_flags() & rx_armed);
    if (!fresh || !rx_handler) break;
    rx_armed &= (uint8_t)~fresh;
    bit_modify(MCP_CANINTE, fresh, 0);
    if (fresh & MCP_INT_RX0) rx_handler();
    if (fresh & MCP_INT_RX1) rx_handler();
  }
#if !defined(__AVR__)
  in_interrupt = 0;
#endif
}

void can_attach_rx(void (*handler)(void)) {
  if (handler) {
    /* The pin interrupt first: frames already waiting pull INT low as soon as CANINTE lets
     * them, and that edge must not come before anyone listens. */
    pin_mode(SEAR_MCP2515_INT_PIN, INPUT);
    irq_attach_pin(SEAR_MCP2515_INT_PIN, IRQ_FALLING, on_interrupt);
  } else {
    irq_detach_pin(SEAR_MCP2515_INT_PIN);
  }
  lock_state state = lock();
  rx_handler = handler;
  rx_armed = handler ? (uint8_t)(MCP_INT_RX0 | MCP_INT_RX1) : 0;
  write_reg(MCP_CANINTE, rx_armed);
  unlock(state);
}

/* ---- Transmission (datasheet section 3) ---- */

uint8_t can_tx_pending(void) {
  lock_state state = lock();
  const uint8_t status = read_status();
  unlock(state);
  uint8_t count = 0;
  for (uint8_t n = 0; n < CAN_TX_BUFFERS; n++) count = (uint8_t)(count + ((status & MCP_STATUS_TXREQ(n)) ? 1u : 0u));
  return count;
}

int8_t can_send(const struct can_frame *frame) {
  lock_state state = lock();
  const uint8_t status = read_status();

  /* The controller sends the pending buffer of highest TXP first, the highest-numbered one
   * among equals (section 3.2): key = 3 TXP + n orders them. Oldest first means each new frame
   * gets a key below every pending one's. A pending buffer must not be written, so the keys
   * only fall until the queue runs empty: under a load that never lets it, a can_send finds no
   * lower key after 12 accepted at the least (tests/mcp2515_driver_test.cpp), and is refused
   * (-1) with a buffer free until the queue has drained. */
  uint8_t lowest_pending = TX_KEYS;
  for (uint8_t n = 0; n < CAN_TX_BUFFERS; n++) {
    if ((status & MCP_STATUS_TXREQ(n)) && tx_key[n] < lowest_pending) lowest_pending = tx_key[n];
  }
  uint8_t best = TX_KEYS;
  for (uint8_t n = 0; n < CAN_TX_BUFFERS; n++) {
    if (status & MCP_STATUS_TXREQ(n)) continue;
    for (uint8_t txp = 4; txp-- > 0;) {
      const uint8_t key = (uint8_t)(3u * txp + n);
      if (key < lowest_pending && (best == TX_KEYS || key > best)) best = key;
    }
  }
  if (best == TX_KEYS) {
    unlock(state);
    return -1;
  }
  const uint8_t buffer = (uint8_t)(best % 3u);

  uint8_t bytes[13];
  id_bytes(frame->id, frame->extended, bytes);
  const uint8_t dlc = frame->dlc > 8 ? 8 : frame->dlc;
  bytes[4] = (uint8_t)(dlc | (frame->remote ? MCP_DLC_RTR : 0));
  const uint8_t data = frame->remote ? 0 : dlc;
  for (uint8_t i = 0; i < data; i++) bytes[5 + i] = frame->data[i];

  write_reg(MCP_TXB_CTRL(buffer), (uint8_t)(best / 3u)); /* TXP, TXREQ still 0 */
  select_chip();
  spi_transfer((uint8_t)(MCP_LOAD_TX0 + 2u * buffer));
  for (uint8_t i = 0; i < 5u + data; i++) spi_transfer(bytes[i]);
  release_chip();
  select_chip();
  spi_transfer(MCP_RTS(buffer));
  release_chip();
  tx_key[buffer] = best;
  unlock(state);
  return 0;
}

/* ---- Errors (datasheet section 6) ---- */

void can_get_counters(struct can_counters *counters) {
  lock_state state = lock();
  uint8_t tec_rec[2];
  read_regs(MCP_TEC, tec_rec, 2);
  const uint8_t eflg = read_reg(MCP_EFLG);
  count_overruns();
  counters->tec = tec_rec[0];
  counters->rec = tec_rec[1];
  counters->state = (eflg & MCP_EFLG_TXBO) ? CAN_BUS_OFF
                    : (eflg & (MCP_EFLG_TXEP | MCP_EFLG_RXEP)) ? CAN_ERROR_PASSIVE
                                                                : CAN_ERROR_ACTIVE;
  counters->rx_overruns = overruns;
  unlock(state);
}

/* ---- Start ---- */

static int8_t rate_listed(uint32_t bitrate) {
  static const uint32_t rates[] = {10000UL, 20000UL, 50000UL, 100000UL, 125000UL, 250000UL, 500000UL, 1000000UL};
  for (uint8_t i = 0; i < sizeof rates / sizeof rates[0]; i++) {
    if (rates[i] == bitrate) return 1;
  }
  return 0;
}

int8_t can_begin(uint32_t bitrate) {
  uint8_t cnf[3];
  /* Only can.h's rates, so a firmware that runs in the simulator runs on the board. */
  if (!rate_listed(bitrate) || mcp2515_bit_timing(SEAR_MCP2515_OSC_HZ, bitrate, cnf) != 0) return -1;
  bitrate_now = bitrate;

  digital_write(SEAR_MCP2515_CS_PIN, HIGH);
  pin_mode(SEAR_MCP2515_CS_PIN, OUTPUT);
  lock_state state = lock();
  select_chip();
  spi_transfer(MCP_RESET);
  release_chip();
  unlock(state);
  /* After RESET the oscillator start-up timer holds the chip for 128 clocks (16 us at 8 MHz),
   * then it is in configuration mode; no answer (MISO reads 0xFF) means no controller. */
  delay_us(20);
  if (wait_mode(MCP_MODE_CONFIG, 2000UL) != 0) return -1;

  state = lock();
  const uint8_t timing[3] = {cnf[2], cnf[1], cnf[0]}; /* CNF3, CNF2, CNF1 at 28h..2Ah */
  write_regs(MCP_CNF3, timing, 3);
  rx_seen = 0;
  rx_older = 0;
  overruns = 0;
  memset(tx_key, 0, sizeof tx_key);
  rx_armed = rx_handler ? (uint8_t)(MCP_INT_RX0 | MCP_INT_RX1) : 0;
  write_reg(MCP_CANINTE, rx_armed);
  unlock(state);

  filtering = 0;
  memset(mask_bits, 0, sizeof mask_bits);
  memset(filter_id, 0, sizeof filter_id);
  memset(filter_ext, 0, sizeof filter_ext);
  apply_filters();
  return (locked_read(MCP_CANSTAT) & MCP_MODE_MASK) == MCP_MODE_NORMAL ? 0 : -1;
}
