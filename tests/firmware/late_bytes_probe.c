/* Queues a long text at 1200 baud (8.3 ms a byte), which keeps leaving the UART long after the
 * call returns, then stops in the way LATE_HOW names (set per build by tests/CMakeLists.txt), 20 ms
 * later: 1 crashes (SIGSEGV); 2 waits for ever, for a run that ends while bytes are still queued;
 * 3 returns from main; 4 aborts (SIGABRT); 5 overflows its stack; 6 hangs with interrupts off. */
#include <hal/hal.h>
#include <signal.h>
#include <stdlib.h>

#if LATE_HOW == 1
volatile int *volatile nowhere;

__attribute__((no_sanitize_address, no_sanitize_undefined)) static void crash(void) {
  signal(SIGSEGV, SIG_DFL);
  *nowhere = 1;
}
#elif LATE_HOW == 5
/* Each frame keeps a page the compiler cannot drop, until the stack's guard page is hit long
 * before `depth_limit` (which only keeps the compiler from calling the recursion endless). */
volatile int depth_limit = 1 << 30;
__attribute__((no_sanitize_address, no_sanitize_undefined, noinline)) static int deeper(int n) {
  volatile char page[4096];
  page[n % 4096] = (char)n;
  if (n >= depth_limit) return 0;
  return deeper(n + 1) + page[(n * 7) % 4096];
}
#elif LATE_HOW == 6
volatile unsigned long spins;
#endif

int main(void) {
  hal_init();
  uart_begin(0, 1200);
  uart_print(0, "0123456789012345678901234567890123456789\n0123456789012345678901234567890123456789\n");
  delay_ms(20);
#if LATE_HOW == 1
  crash();
#elif LATE_HOW == 3
  return 0;
#elif LATE_HOW == 4
  signal(SIGABRT, SIG_DFL);
  abort();
#elif LATE_HOW == 5
  signal(SIGSEGV, SIG_DFL);
  return deeper(0);
#elif LATE_HOW == 6
  irq_disable();
  for (;;) spins++;
#endif
  for (;;) delay_ms(1000);
}
