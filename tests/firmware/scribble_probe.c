/* A firmware that overwrites the memory it shares with the simulator, as a stray pointer could,
 * in the way SCRIBBLE_HOW names (set per build by tests/CMakeLists.txt), after one console line
 * and 100 ms. The simulator must stop it with a report naming what it found, never trust it. */
#include <hal/hal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "find_link.h"

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  uart_print(0, "scribbling\n");
  pin_mode(13, OUTPUT);
  delay_ms(100);
  struct sear_link *link = find_link();
#if SCRIBBLE_HOW == 1
  link->event_count = 1000000000u; /* a count far past the queue */
#elif SCRIBBLE_HOW == 2
  link->events[0] = (struct sear_event){link->clock_ns, 1, SEAR_EVENT_PIN, 200, {0, 0}}; /* no pin 200 */
  link->event_count = 1;
#elif SCRIBBLE_HOW == 3
  link->clock_ns = -5000000000ll; /* time running backwards */
#elif SCRIBBLE_HOW == 4
  memset(link, 0xA5, sizeof *link); /* the whole link */
#elif SCRIBBLE_HOW == 5
  link->events[0] = (struct sear_event){link->clock_ns - 50000000ll, 1, SEAR_EVENT_PIN, 13, {0, 0}}; /* 50 ms ago */
  link->event_count = 1;
#endif
  for (;;) {
    digital_toggle(13);
    delay_ms(1);
  }
}
