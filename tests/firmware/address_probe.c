/* Prints where its stack, its globals and its heap are, and bytes of buffers it never wrote, as a
 * firmware with a pointer or an uninitialised-memory bug would: on a real MCU, and so in SEAR,
 * they are the same in every run. The second stack buffer lies where the C library's formatting
 * just ran (its frames hold the stack protector's canary), where the lockstep hand-off of a delay
 * waited (host times), and where the idle-loop check's timer signals interrupted a computation
 * (registers at host-timed instants); the heap block is one freed and taken again. errno is
 * printed too: the hand-off's futex wait sets it as the host's timing has it (EINTR, EAGAIN), and
 * the C library's free() keeps it in its frame, so it once reached the deep junk. */
#include <errno.h>
#include <hal/hal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int global_counter;

#pragma GCC diagnostic ignored "-Wuninitialized" /* the point of this function */
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
__attribute__((noinline)) static unsigned never_written(void) {
  volatile unsigned char buffer[64]; /* deliberately read before any write */
  unsigned sum = 0;
  for (int i = 0; i < 64; ++i) sum = sum * 31u + buffer[i];
  return sum;
}

/* Deep enough to reach down into the frames snprintf() left. */
__attribute__((noinline)) static unsigned never_written_deep(void) {
  volatile unsigned char buffer[8192];
  unsigned sum = 0;
  for (int i = 0; i < 8192; ++i) sum = sum * 31u + buffer[i];
  return sum;
}

static unsigned heap_reused(void) {
  unsigned char *first = malloc(200);
  memset(first, 0x5A, 200);
  free(first);
  volatile unsigned char *again = malloc(200);
  unsigned sum = 0;
  for (int i = 0; i < 200; ++i) sum = sum * 31u + again[i];
  free((void *)again);
  return sum;
}

static volatile uint32_t ticks;
static void tick(void) { ticks++; }

/* Tens of milliseconds of host computing between HAL calls, for the idle-loop check's signals to
 * land in. */
__attribute__((noinline)) static unsigned compute(void) {
  volatile unsigned x = 1;
  for (unsigned i = 0; i < 30000000u; ++i) x = x * 1664525u + 1013904223u;
  return x;
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
  irq_timer_start(1000, tick); /* an interrupt handler: the idle-loop check starts looking */
  const unsigned computed = compute();
  delay_ms(2); /* a hand-off at the quantum's end */
  const int error = errno;
  snprintf(line, sizeof line, "computed %08x errno %d; after formatting %g: deep junk %08x heap junk %08x\n", computed,
           error, 3.25, never_written_deep(), heap_reused());
  uart_print(0, line);
  free(heap);
  for (;;) delay_ms(100);
}
