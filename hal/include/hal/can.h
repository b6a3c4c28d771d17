/* CAN: one controller on one bus, as an MCP2515 on SPI (the CAN shield of an Arduino Mega) gives
 * it: three transmit buffers sent oldest first, two receive buffers (a frame arriving with both
 * full is lost and counted as an overrun), two acceptance masks over six filters, ISO 11898-1
 * error counters. Standard (11-bit) and extended (29-bit) data and remote frames. Where the real
 * MCP2515 cannot do exactly this (overruns counted once per spell, filters 2-5 feeding only the
 * second buffer), hal/targets/avr/can.c says so at its top. */
#ifndef SEAR_HAL_CAN_H
#define SEAR_HAL_CAN_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CAN_TX_BUFFERS 3
#define CAN_RX_BUFFERS 2
#define CAN_FILTERS 6 /* filters 0-1 use mask 0, filters 2-5 use mask 1 */

struct can_frame {
  uint32_t id;      /* 11 bits, or 29 when extended */
  uint8_t extended; /* 1: a 29-bit identifier */
  uint8_t remote;   /* 1: a remote (RTR) frame, with no data */
  uint8_t dlc;      /* 0..8 */
  uint8_t data[8];
};

enum can_state { CAN_ERROR_ACTIVE = 0, CAN_ERROR_PASSIVE = 1, CAN_BUS_OFF = 2 };

struct can_counters {
  uint8_t tec;          /* transmit error counter (saturates at 255 here; bus-off past 255) */
  uint8_t rec;          /* receive error counter */
  uint8_t state;        /* enum can_state */
  uint16_t rx_overruns; /* frames lost because both receive buffers were full */
};

/* Joins the bus at this bit rate: 10000, 20000, 50000, 100000, 125000, 250000, 500000 or 1000000.
 * Returns 0, or -1 for a rate the controller cannot make. Filters are reset to accept all. */
int8_t can_begin(uint32_t bitrate);
/* Queues a frame; 0 when a transmit buffer took it, -1 when all three are still waiting (on the
 * MCP2515, keeping the order oldest first can also refuse one in twelve under a queue that never
 * drains). */
int8_t can_send(const struct can_frame *frame);
uint8_t can_tx_pending(void);  /* transmit buffers not yet sent (0..3) */
uint8_t can_available(void);   /* received frames waiting (0..2) */
int8_t can_receive(struct can_frame *frame); /* 1: the oldest waiting frame, 0: none */
/* Acceptance, off after can_begin() (every frame is kept) and on from the first call to either:
 * a frame is then kept when, for one filter, its extended flag equals the filter's and
 * (id & mask) == (filter id & mask) with that filter's mask. Masks and filters start at 0. */
void can_set_mask(uint8_t mask, uint32_t bits);
void can_set_filter(uint8_t filter, uint32_t id, uint8_t extended);
void can_get_counters(struct can_counters *counters);
/* handler runs, interrupts disabled, each time a kept frame lands in a receive buffer. */
void can_attach_rx(void (*handler)(void));

#ifdef __cplusplus
}
#endif
#endif
