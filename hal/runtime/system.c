/* Start-up in the simulator: attaching to the link happens before main(); hal_init() only leaves
 * the chip in the state the AVR target's hal_init() does, interrupts enabled. */
#include <hal/system.h>

#include "mcu.h"

#define SEAR_CALL_NAME(name) #name,
static const char *const call_names[] = {SEAR_HAL_CALLS(SEAR_CALL_NAME)};
#undef SEAR_CALL_NAME

void mcu_refuse_before_init(enum sear_call call) {
  mcu_fatal("%s() called before hal_init(): on the board its timers, ADC, UARTs and interrupts are not set "
            "up yet (millis() stays 0); call hal_init() first thing in main()",
            (unsigned)call < SEAR_CALL_COUNT ? call_names[call] : "a HAL call");
}

void hal_init(void) {
  mcu_enter(SEAR_CALL_hal_init);
  sear_mcu.hal_ready = 1;
  sear_mcu.adc_reference = 0;
  sear_mcu.adc_bits = 10;
  sear_mcu.irq_enabled = 1;
  mcu_watch_idle_loops(); /* from here on, `while (true);` halts the MCU */
  mcu_reschedule();
}

void hal_refuse(const char *message) {
  mcu_enter(SEAR_CALL_hal_refuse);
  mcu_fatal("%s", message);
}
