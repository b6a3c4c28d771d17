/* Stops after 300 ms of sim time and one console line, in the way FAIL_HOW (set per build by
 * tests/CMakeLists.txt) names: 1 crashes (SIGSEGV), 2 exits with code 3, 3 hangs without HAL
 * calls, 4 asks for PWM on a pin without a timer. */
#include <hal/hal.h>
#include <stdlib.h>

volatile int *volatile nowhere;
volatile unsigned long spins;

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  uart_print(0, "about to fail\n");
  delay_ms(300);
#if FAIL_HOW == 1
  *nowhere = 1;
#elif FAIL_HOW == 2
  exit(3);
#elif FAIL_HOW == 3
  for (;;) spins++;
#else
  pwm_write(22, 128);
#endif
  for (;;) delay_ms(1000);
}
