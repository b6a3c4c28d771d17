/* The frames the two boards of the CAN example (sensor_node.c, motor_node.c) exchange, and their
 * packing, shared so that both ends agree by construction.
 *
 * One robot, two ATmega2560 boards, each with an MCP2515 CAN shield (CS 10, INT 2) on one bus
 * at 500 kbit/s. Standard 11-bit identifiers; multi-byte fields little-endian (Intel order):
 *
 *   0x120 RANGES  sensor -> motor, every 20 ms, DLC 5:
 *                 bytes 0-1 left range in mm, 2-3 right range in mm (800 = nothing within the
 *                 GP2D12's reach), 4 sequence number (wraps at 256)
 *   0x130 STATUS  motor -> sensor, every 100 ms (the heartbeat), DLC 6:
 *                 byte 0 drive state (enum drive_state), 1-2 left duty, 3-4 right duty
 *                 (-255..255, negative backwards, two's complement), 5 sequence number
 *
 * A node that hears nothing from its peer for PEER_TIMEOUT_MS says so; the motor node stops. */
#ifndef FIRMWARE_CAN_PROTOCOL_H
#define FIRMWARE_CAN_PROTOCOL_H

#include <hal/can.h>
#include <stdint.h>

#define CAN_EXAMPLE_BITRATE 500000UL
#define CAN_ID_RANGES 0x120
#define CAN_ID_STATUS 0x130
#define RANGES_DLC 5
#define STATUS_DLC 6
#define RANGES_PERIOD_MS 20
#define STATUS_PERIOD_MS 100
#define PEER_TIMEOUT_MS 200
#define RANGE_FAR_MM 800 /* the GP2D12's range ends at 80 cm */

enum drive_state { DRIVE_STOPPED, DRIVE_CRUISING, DRIVE_VEERING_LEFT, DRIVE_VEERING_RIGHT, DRIVE_TURNING_LEFT,
                   DRIVE_TURNING_RIGHT, DRIVE_STATES };

static inline void put_u16(uint8_t *at, uint16_t value) {
  at[0] = (uint8_t)value;
  at[1] = (uint8_t)(value >> 8);
}

static inline uint16_t get_u16(const uint8_t *at) { return (uint16_t)(at[0] | (at[1] << 8)); }

static inline void ranges_pack(struct can_frame *frame, uint16_t left_mm, uint16_t right_mm, uint8_t seq) {
  frame->id = CAN_ID_RANGES;
  frame->extended = 0;
  frame->remote = 0;
  frame->dlc = RANGES_DLC;
  put_u16(&frame->data[0], left_mm);
  put_u16(&frame->data[2], right_mm);
  frame->data[4] = seq;
}

/* 1 when the frame is a well-formed RANGES frame. */
static inline uint8_t ranges_unpack(const struct can_frame *frame, uint16_t *left_mm, uint16_t *right_mm,
                                    uint8_t *seq) {
  if (frame->extended || frame->remote || frame->id != CAN_ID_RANGES || frame->dlc < RANGES_DLC) return 0;
  *left_mm = get_u16(&frame->data[0]);
  *right_mm = get_u16(&frame->data[2]);
  *seq = frame->data[4];
  return 1;
}

static inline void status_pack(struct can_frame *frame, uint8_t state, int16_t left, int16_t right, uint8_t seq) {
  frame->id = CAN_ID_STATUS;
  frame->extended = 0;
  frame->remote = 0;
  frame->dlc = STATUS_DLC;
  frame->data[0] = state;
  put_u16(&frame->data[1], (uint16_t)left);
  put_u16(&frame->data[3], (uint16_t)right);
  frame->data[5] = seq;
}

static inline uint8_t status_unpack(const struct can_frame *frame, uint8_t *state, int16_t *left, int16_t *right,
                                    uint8_t *seq) {
  if (frame->extended || frame->remote || frame->id != CAN_ID_STATUS || frame->dlc < STATUS_DLC) return 0;
  *state = frame->data[0];
  *left = (int16_t)get_u16(&frame->data[1]);
  *right = (int16_t)get_u16(&frame->data[3]);
  *seq = frame->data[5];
  return 1;
}

/* Accept only one identifier: both masks all ones, every filter on it (a filter left at 0 would
 * let identifier 0x000 through). */
static inline void can_accept_only(uint32_t id) {
  can_set_mask(0, 0x7FF);
  can_set_mask(1, 0x7FF);
  for (uint8_t f = 0; f < CAN_FILTERS; f++) can_set_filter(f, id, 0);
}

static inline const char *drive_state_name(uint8_t state) {
  static const char *const names[DRIVE_STATES] = {"stopped", "cruising", "veering left", "veering right",
                                                  "turning left", "turning right"};
  return state < DRIVE_STATES ? names[state] : "?";
}

#endif
