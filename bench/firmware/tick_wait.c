/* A main loop paced by a 1 kHz timer interrupt, waiting for each tick in `while (!flag) {}`: what
 * the idle-loop check costs per tick, as the run's real-time factor. */
#include <hal/hal.h>

static volatile uint8_t ticked;
static void tick(void) { ticked = 1; }

int main(void) {
  hal_init();
  pin_mode(13, OUTPUT);
  irq_timer_start(1000, tick);
  for (;;) {
    while (!ticked) {
    }
    ticked = 0;
    digital_toggle(13);
  }
}
