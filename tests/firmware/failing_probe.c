/* Stops after 300 ms of sim time and one console line, in the way FAIL_HOW (set per build by
 * tests/CMakeLists.txt) names: 1 crashes (SIGSEGV), 2 exits with code 3 (and a destructor then
 * calls the HAL), 3 hangs without HAL calls, 4 asks for PWM on a pin without a timer. */
#include <hal/hal.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>

volatile int *volatile nowhere;

#if FAIL_HOW == 1
/* A real invalid store. Under the sanitizers (SEAR_SANITIZE) they would catch it first and exit
 * with code 1, so they are kept out of this one function and their SIGSEGV handler is removed. */
__attribute__((no_sanitize_address, no_sanitize_undefined)) static void crash(void) {
  signal(SIGSEGV, SIG_DFL);
  *nowhere = 1;
}
#endif

/* Runs after exit(): the HAL must still answer, without waiting for a turn that never comes. */
__attribute__((destructor)) static void goodbye(void) {
  uart_print(0, "goodbye\n");
  delay_ms(5);
}
volatile unsigned long spins;

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  uart_print(0, "about to fail\n");
  printf("on its own stdout before failing\n"); /* no newline flush on a file: unbuffered, or lost */
  delay_ms(300);
#if FAIL_HOW == 1
  crash();
#elif FAIL_HOW == 2
  exit(3);
#elif FAIL_HOW == 3
  for (;;) spins++;
#else
  pwm_write(22, 128);
#endif
  for (;;) delay_ms(1000);
}
