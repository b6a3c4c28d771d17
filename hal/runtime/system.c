/* Start-up in the simulator: attaching to the link happens before main(); hal_init() only leaves
 * the chip in the state the AVR target's hal_init() does, interrupts enabled. */
#include <hal/system.h>

#include "mcu.h"

void hal_init(void) {
  mcu_enter(SEAR_CALL_hal_init);
  sear_mcu.adc_reference = 0;
  sear_mcu.adc_bits = 10;
  sear_mcu.irq_enabled = 1;
  mcu_reschedule();
}

void hal_refuse(const char *message) {
  mcu_enter(SEAR_CALL_hal_refuse);
  mcu_fatal("%s", message);
}
