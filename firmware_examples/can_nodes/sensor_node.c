/* CAN example, sensor board: two Sharp GP2D12 rangers looking ahead-left and ahead-right (ADC 0
 * and 1) measured every 20 ms and sent to the motor board as a RANGES frame; the motor board's
 * STATUS heartbeat is watched (polled, with the acceptance filters passing only it).
 * The frames and the whole two-board setup: can_protocol.h. Project: project.xml beside it.
 *
 * Console (UART 0, 115200 baud), one line per event:
 *   tx 0x120 L=0.43 R=0.80 n=17          a RANGES frame queued (metres, sequence number)
 *   tx 0x120 busy                        the three transmit buffers are full (nobody acknowledges)
 *   rx 0x130 turning left L=-130 R=130   the motor board's state, printed when it changes
 *   peer lost / peer up                  no STATUS for 200 ms / STATUS again
 *   can: no controller                   can_begin failed; retried every second */
#include <hal/hal.h>
#include <stdio.h>

#include "can_protocol.h"

#define IR_LEFT_CHANNEL 0
#define IR_RIGHT_CHANNEL 1

/* Distance from a GP2D12 reading (10-bit, 5 V reference), the usual fit to the datasheet's curve:
 * mm = 67870 / (code - 3) - 40, good over 100..800 mm; below code 84 nothing is within reach. */
static uint16_t ir_mm(uint8_t channel) {
  const uint16_t code = adc_read(channel);
  if (code < 84) return RANGE_FAR_MM;
  const uint16_t mm = (uint16_t)(67870UL / (code - 3u) - 40u);
  return mm > RANGE_FAR_MM ? RANGE_FAR_MM : mm;
}

static void say(const char *text) { uart_print(0, text); }

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  say("sensor node: ready\r\n");
  while (can_begin(CAN_EXAMPLE_BITRATE) != 0) {
    say("can: no controller\r\n");
    delay_ms(1000);
  }
  can_accept_only(CAN_ID_STATUS);
  delay_ms(100); /* the rangers' first measurement is ready after one 38 ms cycle */

  char line[48];
  uint8_t seq = 0, busy = 0, peer_up = 0, peer_state = DRIVE_STATES;
  uint32_t next_send = millis(), last_status = 0;
  for (;;) {
    const uint32_t now = millis();
    if ((int32_t)(now - next_send) >= 0) {
      /* Every 20 ms; after a stall longer than that, from now on rather than in a burst. */
      next_send = (uint32_t)(now - next_send) >= RANGES_PERIOD_MS ? now + RANGES_PERIOD_MS : next_send + RANGES_PERIOD_MS;
      const uint16_t left = ir_mm(IR_LEFT_CHANNEL), right = ir_mm(IR_RIGHT_CHANNEL);
      struct can_frame out;
      ranges_pack(&out, left, right, seq);
      if (can_send(&out) == 0) {
        snprintf(line, sizeof line, "tx 0x%03X L=%u.%02u R=%u.%02u n=%u\r\n", (unsigned)CAN_ID_RANGES, left / 1000u,
                 (left % 1000u) / 10u, right / 1000u, (right % 1000u) / 10u, (unsigned)seq);
        say(line);
        busy = 0;
        seq++;
      } else if (!busy) {
        say("tx 0x120 busy\r\n");
        busy = 1;
      }
    }

    struct can_frame in;
    while (can_receive(&in)) {
      uint8_t state, status_seq;
      int16_t left_duty, right_duty;
      if (!status_unpack(&in, &state, &left_duty, &right_duty, &status_seq)) continue;
      last_status = millis();
      if (!peer_up) {
        say("peer up\r\n");
        peer_up = 1;
      }
      if (state != peer_state) {
        snprintf(line, sizeof line, "rx 0x%03X %s L=%d R=%d\r\n", (unsigned)CAN_ID_STATUS, drive_state_name(state),
                 left_duty, right_duty);
        say(line);
        peer_state = state;
      }
    }
    if (peer_up && (uint32_t)(millis() - last_status) > PEER_TIMEOUT_MS) {
      say("peer lost\r\n");
      peer_up = 0;
      peer_state = DRIVE_STATES;
    }
    delay_ms(1);
  }
}
