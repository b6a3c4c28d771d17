/* The least a firmware can do: hand every quantum straight back. What the lockstep costs. */
#include <hal/hal.h>

int main(void) {
  hal_init();
  for (;;) delay_ms(1);
}
