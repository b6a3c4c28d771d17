/* When things happen in the firmware's virtual time: every HAL call enters here, which hands over
 * at quantum ends, applies samples and received bytes as they fall due, and runs interrupts. */
#ifndef SEAR_HAL_RUNTIME_SCHEDULER_H
#define SEAR_HAL_RUNTIME_SCHEDULER_H

#include <stdint.h>

#include "mcu_state.h"

/* The slow path of every HAL call: hands over at quantum ends, applies what fell due, runs
 * interrupts. Called only when the clock has reached next_due_ns. */
void mcu_service(void);

/* Stops the MCU with a report: `call` came before hal_init(). */
void mcu_refuse_before_init(enum sear_call call) __attribute__((noreturn));

/* On the board, a call before hal_init() finds its timers stopped (millis() stays 0), the ADC
 * off, and a begun UART reset by the hal_init() that follows; natively each would work, and the
 * firmware would fail only on the board. The port registers need no set-up: pins work before it,
 * as a library's constructor (LiquidCrystal's pinMode) expects. */
static inline int mcu_allowed_before_init(enum sear_call call) {
  return call == SEAR_CALL_hal_init || call == SEAR_CALL_hal_refuse || call == SEAR_CALL_pin_mode ||
         call == SEAR_CALL_digital_read || call == SEAR_CALL_digital_write || call == SEAR_CALL_digital_toggle;
}

/* Charges a HAL call: records it for reports, serves what fell due, and returns the time at
 * which the call acts; its cost is added after. */
static inline int64_t mcu_enter(enum sear_call call) {
  struct sear_link *link = sear_mcu.link;
  link->last_call = (uint32_t)call;
  link->calls++;
  if (__builtin_expect(!sear_mcu.hal_ready, 0) && !mcu_allowed_before_init(call)) mcu_refuse_before_init(call);
  if (link->clock_ns >= sear_mcu.next_due_ns) mcu_service();
  const int64_t now = link->clock_ns;
  link->clock_ns = now + sear_mcu.cost_ns;
  return now;
}

/* Moves the clock to t_ns, handing over at each quantum end and running interrupts at the
 * moment they fall due, as they would during a busy-wait on a real chip. */
void mcu_advance_to(int64_t t_ns);

/* Recomputes next_due_ns after anything that changed what is pending. */
void mcu_reschedule(void);

/* The earliest sample, received byte or timer tick still to come. */
int64_t mcu_earliest_input(void);

/* Takes the samples and bytes the simulator put in the link for the quantum just begun. */
void mcu_take_quantum(void);

/* A byte on its way in, due at time_ns (the end of its stop bit). */
void mcu_uart_arrive(uint8_t port, uint8_t byte, int64_t time_ns);

#endif
