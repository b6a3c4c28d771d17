/* Prints where its stack, its globals and its heap are, and bytes of a buffer it never wrote,
 * as a firmware with a pointer or an uninitialised-memory bug would: on a real MCU, and so in
 * SEAR, they are the same in every run. */
#include <hal/hal.h>
#include <stdio.h>
#include <stdlib.h>

int global_counter;

#pragma GCC diagnostic ignored "-Wuninitialized" /* the point of this function */
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
__attribute__((noinline)) static unsigned never_written(void) {
  volatile unsigned char buffer[64]; /* deliberately read before any write */
  unsigned sum = 0;
  for (int i = 0; i < 64; ++i) sum = sum * 31u + buffer[i];
  return sum;
}

int main(void) {
  char line[160];
  int local = 0;
  hal_init();
  uart_begin(0, 115200);
  void *heap = malloc(100);
  snprintf(line, sizeof line, "stack %p global %p heap %p junk %08x\n", (void *)&local, (void *)&global_counter,
           heap, never_written());
  uart_print(0, line);
  free(heap);
  for (;;) delay_ms(100);
}
