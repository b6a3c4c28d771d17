/* Writes output as fast as it can, in the way FLOOD_HOW names (set per build by
 * tests/CMakeLists.txt): 1 toggles a pin every microsecond, so the pin waveform grows quickly;
 * 2 prints on its own standard output in a loop; 3 toggles a pin in a loop that, with
 * hal_call_cycles="0", takes no simulated time at all. */
#include <hal/hal.h>
#include <stdio.h>

int main(void) {
  hal_init();
  pin_mode(13, OUTPUT);
  for (unsigned long n = 0;; ++n) {
#if FLOOD_HOW == 1
    digital_toggle(13);
    delay_us(1);
#elif FLOOD_HOW == 2
    printf("host line %lu, padding the log to reach its limit quickly\n", n);
    delay_us(10);
#else
    digital_toggle(13);
#endif
  }
}
