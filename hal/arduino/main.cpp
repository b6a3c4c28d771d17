// The sketch's main(), as the core's: setup() once, then loop() and the serial events forever.
#include <Arduino.h>
#include <hal/system.h>

int main() {
  hal_init();
  setup();
  for (;;) {
    loop();
    serialEventRun();
  }
}
