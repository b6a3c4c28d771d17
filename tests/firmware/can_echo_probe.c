/* For vcan_test.cpp, a node at the far end of `sear run --can`: at 500 kbit/s it answers every
 * frame it receives with the same frame under identifier + 1 (same width, flags, length and data),
 * and every 10 ms, from 10 ms on, sends its own frame 0x0A0 with 4 bytes: its number (low byte
 * first, 16 bits), then 0xC0 0xDE. */
#include <hal/hal.h>

#define OWN_ID 0x0A0
#define OWN_PERIOD_US 10000UL

static void send(const struct can_frame *f) {
  /* All three transmit buffers still waiting: wait on the bus, as a firmware must. */
  while (can_send(f) != 0) delay_us(100);
}

int main(void) {
  hal_init();
  can_begin(500000);
  uint16_t count = 0;
  uint32_t next_us = OWN_PERIOD_US;
  for (;;) {
    struct can_frame f;
    while (can_receive(&f) == 1) {
      f.id = (f.id + 1) & (f.extended ? 0x1FFFFFFFUL : 0x7FFUL);
      send(&f);
    }
    if ((int32_t)(micros() - next_us) >= 0) {
      struct can_frame own = {OWN_ID, 0, 0, 4, {(uint8_t)(count & 0xFF), (uint8_t)(count >> 8), 0xC0, 0xDE}};
      send(&own);
      ++count;
      next_us += OWN_PERIOD_US;
    }
    /* Looks every 200 us: the shortest frame at 500 kbit/s (47 bits with the interframe space)
     * takes 94 us, so even back-to-back frames fill the two receive buffers no sooner than
     * 188 us and overrun them no sooner than 282 us after a look. */
    delay_us(200);
  }
}
