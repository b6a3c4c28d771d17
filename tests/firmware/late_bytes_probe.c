/* Queues a long text at 1200 baud (8.3 ms a byte), which keeps leaving the UART long after the
 * call returns, then stops in the way LATE_HOW names (set per build by tests/CMakeLists.txt):
 * 1 crashes 20 ms later; 2 waits for ever, for a run that ends while bytes are still queued. */
#include <hal/hal.h>
#include <signal.h>

#if LATE_HOW == 1
volatile int *volatile nowhere;

__attribute__((no_sanitize_address, no_sanitize_undefined)) static void crash(void) {
  signal(SIGSEGV, SIG_DFL);
  *nowhere = 1;
}
#endif

int main(void) {
  hal_init();
  uart_begin(0, 1200);
  uart_print(0, "0123456789012345678901234567890123456789\n0123456789012345678901234567890123456789\n");
  delay_ms(20);
#if LATE_HOW == 1
  crash();
#endif
  for (;;) delay_ms(1000);
}
