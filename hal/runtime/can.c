/* The CAN controller of hal/can.h in the firmware's process: transmit buffers whose frames go to
 * the simulated bus as events, and the bus's records (receptions and the outcome of each send)
 * applied at their times through acceptance filters into two receive buffers. */
#include <hal/can.h>
#include <stddef.h>
#include <string.h>

#include "can_controller.h"
#include "mcu.h"

static int supported_rate(uint32_t bitrate) {
  static const uint32_t rates[] = {SEAR_CAN_BITRATES};
  for (size_t i = 0; i < sizeof rates / sizeof rates[0]; ++i)
    if (rates[i] == bitrate) return 1;
  return 0;
}

int8_t can_begin(uint32_t bitrate) {
  const int64_t now = mcu_enter(SEAR_CALL_can_begin);
  struct mcu_can *c = &sear_mcu.can;
  if (!supported_rate(bitrate)) return -1;
  /* As the MCP2515's reset: queued frames are dropped (the simulator's bus drops them too) and the
   * overrun count starts again. */
  c->bitrate = bitrate;
  c->tx_pending = 0;
  c->rx_overruns = 0;
  c->rx_count = 0;
  c->rx_head = 0;
  c->rx_pending = 0;
  c->filtering = 0;
  memset(c->mask, 0, sizeof c->mask);
  memset(c->filter_id, 0, sizeof c->filter_id);
  memset(c->filter_extended, 0, sizeof c->filter_extended);
  mcu_emit(SEAR_EVENT_CAN_BEGIN, 0, bitrate, now);
  return 0;
}

int8_t can_send(const struct can_frame *frame) {
  const int64_t now = mcu_enter(SEAR_CALL_can_send);
  struct mcu_can *c = &sear_mcu.can;
  if (!frame) mcu_fatal("can_send(NULL)");
  if (frame->dlc > 8) mcu_fatal("can_send: dlc %u (a classical CAN frame holds 0..8 bytes)", frame->dlc);
  if (frame->id > (frame->extended ? 0x1FFFFFFFu : 0x7FFu))
    mcu_fatal("can_send: id 0x%lx does not fit %s", (unsigned long)frame->id,
              frame->extended ? "29 bits" : "11 bits (set .extended for a 29-bit id)");
  if (!c->bitrate || c->tx_pending >= CAN_TX_BUFFERS) return -1;
  c->tx_pending++;
  const unsigned flags = (frame->extended ? SEAR_CAN_EXTENDED : 0u) | (frame->remote ? SEAR_CAN_REMOTE : 0u);
  uint32_t half[2] = {0, 0};
  for (int i = 0; i < 8; ++i)
    if (!frame->remote && i < frame->dlc) half[i / 4] |= (uint32_t)frame->data[i] << (8 * (i % 4));
  mcu_emit(SEAR_EVENT_CAN_TX, (uint8_t)(frame->dlc | flags << 4), frame->id, now);
  mcu_emit(SEAR_EVENT_CAN_DATA, 0, half[0], now);
  mcu_emit(SEAR_EVENT_CAN_DATA, 1, half[1], now);
  return 0;
}

uint8_t can_tx_pending(void) {
  mcu_enter(SEAR_CALL_can_tx_pending);
  return sear_mcu.can.tx_pending;
}

uint8_t can_available(void) {
  mcu_enter(SEAR_CALL_can_available);
  return sear_mcu.can.rx_count;
}

int8_t can_receive(struct can_frame *frame) {
  mcu_enter(SEAR_CALL_can_receive);
  struct mcu_can *c = &sear_mcu.can;
  if (!frame) mcu_fatal("can_receive(NULL)");
  if (!c->rx_count) return 0;
  *frame = c->rx[c->rx_head];
  c->rx_head = (uint8_t)((c->rx_head + 1) % CAN_RX_BUFFERS);
  c->rx_count--;
  return 1;
}

void can_set_mask(uint8_t mask, uint32_t bits) {
  mcu_enter(SEAR_CALL_can_set_mask);
  if (mask > 1) mcu_fatal("can_set_mask(%u): the controller has masks 0 and 1", mask);
  sear_mcu.can.mask[mask] = bits & 0x1FFFFFFFu;
  sear_mcu.can.filtering = 1;
}

void can_set_filter(uint8_t filter, uint32_t id, uint8_t extended) {
  mcu_enter(SEAR_CALL_can_set_filter);
  if (filter >= CAN_FILTERS) mcu_fatal("can_set_filter(%u): the controller has filters 0..%d", filter, CAN_FILTERS - 1);
  sear_mcu.can.filter_id[filter] = id & 0x1FFFFFFFu;
  sear_mcu.can.filter_extended[filter] = extended ? 1 : 0;
  sear_mcu.can.filtering = 1;
}

void can_get_counters(struct can_counters *counters) {
  mcu_enter(SEAR_CALL_can_get_counters);
  const struct mcu_can *c = &sear_mcu.can;
  if (!counters) mcu_fatal("can_get_counters(NULL)");
  counters->tec = c->tec;
  counters->rec = c->rec;
  /* ISO 11898-1 fault confinement: error passive from 128; bus-off is never reached here, as
   * the simulated bus has no bit errors and acknowledgement errors stop counting at 128. */
  counters->state = c->tec >= 128 || c->rec >= 128 ? CAN_ERROR_PASSIVE : CAN_ERROR_ACTIVE;
  counters->rx_overruns = c->rx_overruns;
}

void can_attach_rx(void (*handler)(void)) {
  mcu_enter(SEAR_CALL_can_attach_rx);
  sear_mcu.can.rx_handler = handler;
  sear_mcu.can.rx_pending = 0;
  mcu_watch_idle_loops();
}

static int kept(const struct mcu_can *c, uint32_t id, int extended) {
  if (!c->filtering) return 1;
  for (int f = 0; f < CAN_FILTERS; ++f) {
    const uint32_t m = c->mask[f < 2 ? 0 : 1];
    if (c->filter_extended[f] == extended && (id & m) == (c->filter_id[f] & m)) return 1;
  }
  return 0;
}

void mcu_can_apply(const struct sear_link_can *r) {
  struct mcu_can *c = &sear_mcu.can;
  c->tec = r->tec;
  c->rec = r->rec;
  if (r->record == SEAR_CAN_SENT) {
    if (c->tx_pending) c->tx_pending--;
    return;
  }
  if (r->record != SEAR_CAN_RECEIVED || !c->bitrate) return;
  const int extended = (r->flags & SEAR_CAN_EXTENDED) != 0;
  if (!kept(c, r->id, extended)) return;
  if (c->rx_count == CAN_RX_BUFFERS) {
    c->rx_overruns++;
    return;
  }
  struct can_frame *f = &c->rx[(c->rx_head + c->rx_count++) % CAN_RX_BUFFERS];
  memset(f, 0, sizeof *f);
  f->id = r->id;
  f->extended = (uint8_t)extended;
  f->remote = (r->flags & SEAR_CAN_REMOTE) != 0;
  f->dlc = r->dlc > 8 ? 8 : r->dlc;
  if (!f->remote) memcpy(f->data, r->data, f->dlc);
  if (c->rx_handler) c->rx_pending = 1;
}

void mcu_can_arrive(const struct sear_link_can *r) {
  struct mcu_can *c = &sear_mcu.can;
  if (c->arrival_count == MCU_CAN_ARRIVALS) return; /* the simulator sends at most this many */
  c->arrivals[(c->arrival_head + c->arrival_count++) % MCU_CAN_ARRIVALS] = *r;
}
