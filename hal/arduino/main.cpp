// The sketch's main(), as the core's: setup() once, then loop() and the serial events forever.
#include <Arduino.h>
#include <hal/system.h>

int main() {
  hal_init();
  setup();
  for (;;) {
    loop();
    serialEventRun();
    // Each pass costs the chip cycles (the call, serialEventRun's checks) even when loop() is
    // empty, the idiom for "done": one HAL call's cost stands for them, so that time, interrupts
    // and the world go on as on the chip instead of the clock standing still.
    (void)micros();
  }
}
