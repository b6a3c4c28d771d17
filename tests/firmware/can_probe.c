/* CAN on the simulated bus, seen from one controller: at 10 ms it queues PROBE_BURST frames with
 * identifier PROBE_ID (data: the frame's number, then 0x11 0x22 ...), reads nothing before
 * PROBE_READ_AFTER_MS, then prints every frame it receives with the time it saw it, and its
 * counters at 250 ms. With PROBE_FILTER set it keeps only that identifier (both masks set, as
 * the MCP2515 needs). The console lines:
 *   tx <us> <id> <0: queued, -1: buffers full>
 *   rx <us> <id> <dlc> <data hex>
 *   counters <tec> <rec> <state> <overruns> <pending> */
#include <hal/hal.h>
#include <stdio.h>

#ifndef PROBE_ID
#define PROBE_ID 0x100
#endif
#ifndef PROBE_BURST
#define PROBE_BURST 1
#endif
#ifndef PROBE_READ_AFTER_MS
#define PROBE_READ_AFTER_MS 0
#endif
#ifndef PROBE_FILTER
#define PROBE_FILTER 0
#endif

static void print(const char *line) { uart_print(0, line); }

int main(void) {
  char line[96];
  hal_init();
  uart_begin(0, 1000000);
  can_begin(500000);
  if (PROBE_FILTER) {
    can_set_mask(0, 0x7FF);
    can_set_mask(1, 0x7FF);
    for (uint8_t f = 0; f < CAN_FILTERS; ++f) can_set_filter(f, PROBE_FILTER, 0);
  }
  delay_us(10000 - micros());
  for (int i = 0; i < PROBE_BURST; ++i) {
    struct can_frame f = {PROBE_ID, 0, 0, 8, {(uint8_t)i, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77}};
    const unsigned long at = (unsigned long)micros();
    snprintf(line, sizeof line, "tx %lu %03lx %d\n", at, (unsigned long)f.id, can_send(&f));
    print(line);
  }
  int counted = 0;
  for (;;) {
    struct can_frame f;
    if (millis() + 1 > PROBE_READ_AFTER_MS) {
      while (can_receive(&f)) {
        int n = snprintf(line, sizeof line, "rx %lu %03lx %u ", (unsigned long)micros(), (unsigned long)f.id, f.dlc);
        for (uint8_t i = 0; i < f.dlc; ++i) n += snprintf(line + n, sizeof line - (size_t)n, "%02x", f.data[i]);
        snprintf(line + n, sizeof line - (size_t)n, "\n");
        print(line);
      }
    }
    if (!counted && millis() >= 250) {
      struct can_counters c;
      can_get_counters(&c);
      snprintf(line, sizeof line, "counters %u %u %u %u %u\n", c.tec, c.rec, c.state, c.rx_overruns, can_tx_pending());
      print(line);
      counted = 1;
    }
    delay_us(100);
  }
}
