/* UBX framing: see ubx.h. A frame is B5 62, class, id, length (LE16), payload, CK_A, CK_B, the
 * 8-bit Fletcher sums over class to the payload's end. */
#include "ubx.h"

#include <hal/hal.h>

#define SYNC1 0xB5
#define SYNC2 0x62
#define CLASS_ACK 0x05
#define ACK_NAK 0x00
#define ACK_ACK 0x01

static uint8_t ack_kind, ack_cls, ack_id;

void ubx_send(uint8_t port, uint8_t cls, uint8_t id, const uint8_t *payload, uint16_t length) {
  uint8_t head[4] = {cls, id, (uint8_t)(length & 0xFF), (uint8_t)(length >> 8)};
  uint8_t a = 0, b = 0;
  ack_kind = UBX_ACK_NONE;
  uart_write(port, SYNC1);
  uart_write(port, SYNC2);
  for (uint8_t i = 0; i < 4; ++i) {
    uart_write(port, head[i]);
    a = (uint8_t)(a + head[i]);
    b = (uint8_t)(b + a);
  }
  for (uint16_t i = 0; i < length; ++i) {
    uart_write(port, payload[i]);
    a = (uint8_t)(a + payload[i]);
    b = (uint8_t)(b + a);
  }
  uart_write(port, a);
  uart_write(port, b);
}

/* Only ACK messages matter here (2-byte payload), so the receiver keeps just those: position 0
 * hunts for B5, then 62, class, id, length (2), payload (2), CK_A, CK_B. */
static uint8_t at, frame[10];

void ubx_feed(uint8_t byte) {
  if (at == 0) {
    if (byte == SYNC1) at = 1;
    return;
  }
  if (at == 1) {
    at = byte == SYNC2 ? 2 : (byte == SYNC1 ? 1 : 0);
    return;
  }
  frame[at - 2u] = byte;
  at++;
  /* class ACK with a 2-byte payload, or give up on this frame */
  if ((at == 3 && frame[0] != CLASS_ACK) || (at == 5 && frame[2] != 2) || (at == 6 && frame[3] != 0)) {
    at = byte == SYNC1 ? 1 : 0;
    return;
  }
  if (at < 10) return;
  at = 0;
  uint8_t a = 0, b = 0;
  for (uint8_t i = 0; i < 6; ++i) {
    a = (uint8_t)(a + frame[i]);
    b = (uint8_t)(b + a);
  }
  if (a != frame[6] || b != frame[7]) return;
  ack_kind = frame[1] == ACK_ACK ? UBX_ACK_ACK : (frame[1] == ACK_NAK ? UBX_ACK_NAK : UBX_ACK_NONE);
  ack_cls = frame[4];
  ack_id = frame[5];
}

uint8_t ubx_ack(uint8_t cls, uint8_t id) { return ack_cls == cls && ack_id == id ? ack_kind : UBX_ACK_NONE; }
