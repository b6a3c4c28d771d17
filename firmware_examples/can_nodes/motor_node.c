/* CAN example, motor board: takes the sensor board's RANGES frames in a CAN receive interrupt
 * (acceptance filters pass only those), steers away from what the rangers see as the obstacle
 * avoider does (firmware_examples/avoider), drives the Arduino Motor Shield R3, and sends a
 * STATUS heartbeat every 100 ms. No RANGES for 200 ms: it stops and brakes until they return.
 * The frames and the whole two-board setup: can_protocol.h. Project: project.xml beside it.
 *
 * Console (UART 0, 115200 baud), one line per event:
 *   rx 0x120 L=0.43 R=0.80 n=17             a RANGES frame (metres, its sequence number)
 *   drive turning left L=-130 R=130         a new drive state and its duties
 *   tx 0x130 busy                           the heartbeat found all transmit buffers full
 *   peer lost: stop / peer up               no RANGES for 200 ms / RANGES again
 *   can: no controller                      can_begin failed; retried every second */
#include <hal/hal.h>
#include <stdio.h>

#include "../lib/motor_shield.h"
#include "can_protocol.h"

#define CRUISE 150 /* PWM duty of 255 */
#define TURN 130
#define NEAR_MM 300        /* turn away below this */
#define VEER_MM 550        /* steer away below this */
#define CLEAR_MARGIN_MM 100 /* stop veering only this far beyond VEER_MM, or it would dither */

/* The latest RANGES frame, written by the receive interrupt. */
static volatile uint16_t rx_left_mm, rx_right_mm;
static volatile uint8_t rx_seq, rx_fresh;
static volatile uint32_t rx_at_ms;

static void on_can_rx(void) {
  struct can_frame frame;
  uint16_t left, right;
  uint8_t seq;
  while (can_receive(&frame)) {
    if (!ranges_unpack(&frame, &left, &right, &seq)) continue;
    rx_left_mm = left;
    rx_right_mm = right;
    rx_seq = seq;
    rx_at_ms = millis();
    rx_fresh = 1;
  }
}

static uint8_t decide(uint8_t state, uint16_t left, uint16_t right) {
  if (left < NEAR_MM || right < NEAR_MM) {
    /* Turn on the spot away from the nearer side, and keep turning the same way until clear,
     * so that a corner cannot make it dither. */
    if (state == DRIVE_TURNING_LEFT || state == DRIVE_TURNING_RIGHT) return state;
    return left < right ? DRIVE_TURNING_RIGHT : DRIVE_TURNING_LEFT;
  }
  if (left < VEER_MM || (state == DRIVE_VEERING_RIGHT && left < VEER_MM + CLEAR_MARGIN_MM)) return DRIVE_VEERING_RIGHT;
  if (right < VEER_MM || (state == DRIVE_VEERING_LEFT && right < VEER_MM + CLEAR_MARGIN_MM)) return DRIVE_VEERING_LEFT;
  return DRIVE_CRUISING;
}

static void duties(uint8_t state, int16_t *left, int16_t *right) {
  switch (state) {
    case DRIVE_CRUISING: *left = CRUISE; *right = CRUISE; break;
    case DRIVE_VEERING_LEFT: *left = CRUISE / 3; *right = CRUISE; break;
    case DRIVE_VEERING_RIGHT: *left = CRUISE; *right = CRUISE / 3; break;
    case DRIVE_TURNING_LEFT: *left = -TURN; *right = TURN; break;
    case DRIVE_TURNING_RIGHT: *left = TURN; *right = -TURN; break;
    default: *left = 0; *right = 0; break;
  }
}

static void say(const char *text) { uart_print(0, text); }

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  motors_begin();
  motors_brake();
  say("motor node: ready\r\n");
  while (can_begin(CAN_EXAMPLE_BITRATE) != 0) {
    say("can: no controller\r\n");
    delay_ms(1000);
  }
  can_accept_only(CAN_ID_RANGES);
  can_attach_rx(on_can_rx);

  char line[48];
  uint8_t state = DRIVE_STOPPED, peer_up = 0, status_seq = 0, busy = 0;
  int16_t left_duty = 0, right_duty = 0;
  uint32_t next_status = millis();
  for (;;) {
    irq_disable();
    const uint8_t fresh = rx_fresh;
    const uint16_t left = rx_left_mm, right = rx_right_mm;
    const uint8_t seq = rx_seq;
    const uint32_t heard_at = rx_at_ms;
    rx_fresh = 0;
    irq_enable();
    /* Read after the copy, so that a frame taken meanwhile is never newer than now. */
    const uint32_t now = millis();

    uint8_t next = state;
    if (fresh) {
      snprintf(line, sizeof line, "rx 0x%03X L=%u.%02u R=%u.%02u n=%u\r\n", (unsigned)CAN_ID_RANGES, left / 1000u,
               (left % 1000u) / 10u, right / 1000u, (right % 1000u) / 10u, (unsigned)seq);
      say(line);
      if (!peer_up) {
        say("peer up\r\n");
        peer_up = 1;
      }
      next = decide(state, left, right);
    } else if (peer_up && (uint32_t)(now - heard_at) > PEER_TIMEOUT_MS) {
      say("peer lost: stop\r\n");
      peer_up = 0;
      next = DRIVE_STOPPED;
    }
    if (next != state) {
      state = next;
      duties(state, &left_duty, &right_duty);
      if (state == DRIVE_STOPPED)
        motors_brake();
      else
        motors_drive(left_duty, right_duty);
      snprintf(line, sizeof line, "drive %s L=%d R=%d\r\n", drive_state_name(state), left_duty, right_duty);
      say(line);
    }

    if ((int32_t)(now - next_status) >= 0) {
      /* Every 100 ms; after a stall longer than that, from now on rather than in a burst. */
      next_status = (uint32_t)(now - next_status) >= STATUS_PERIOD_MS ? now + STATUS_PERIOD_MS : next_status + STATUS_PERIOD_MS;
      struct can_frame out;
      status_pack(&out, state, left_duty, right_duty, status_seq);
      if (can_send(&out) == 0) {
        status_seq++;
        busy = 0;
      } else if (!busy) {
        say("tx 0x130 busy\r\n");
        busy = 1;
      }
    }
    delay_ms(1);
  }
}
