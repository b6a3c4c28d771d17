/* Test firmware for a project's build flags: it needs a define (REPEAT, from <firmware defines>),
 * a header from an include folder (<firmware includes>), C11 (<firmware c_std>: _Static_assert)
 * and a C++ source (twice.cpp) linked in; it says what they gave it on its console. */
#include <hal/hal.h>
#include <stdio.h>

#include "greeting.h"

#ifndef REPEAT
#error "REPEAT must come from the project's <firmware defines>"
#endif
_Static_assert(REPEAT > 0, "REPEAT counts lines");

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  char line[48];
  for (int i = 0; i < REPEAT; ++i) {
    snprintf(line, sizeof line, "%s %d twice %d\r\n", GREETING, i, twice(i));
    uart_print(0, line);
  }
  for (;;) delay_ms(100);
}
