/* Times HAL calls that need no exchange with the simulator: run with hal_call_cycles="0", so the
 * calls never move the clock to a quantum's end. Host-only: it reads the host's clock to time
 * itself, which no real firmware could do. */
#define _POSIX_C_SOURCE 199309L
#include <hal/hal.h>
#include <stdio.h>
#include <time.h>

static double now_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  pin_mode(2, INPUT_PULLUP);
  enum { CALLS = 20000000 };
  volatile uint8_t sink = 0;
  const double start = now_ns();
  for (long i = 0; i < CALLS; ++i) sink = (uint8_t)(sink + digital_read(2));
  const double per_call = (now_ns() - start) / CALLS;
  char line[64];
  snprintf(line, sizeof line, "ns per HAL call %.2f\n", per_call);
  uart_print(0, line);
  for (;;) delay_ms(1);
}
