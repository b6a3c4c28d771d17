/* Interrupt sources and the global enable: handlers are recorded here and run by the scheduler
 * at the first HAL call after their cause falls due. */
#include <hal/irq.h>
#include <stddef.h>

#include "board.h"
#include "mcu.h"

void irq_attach_pin(uint8_t pin, uint8_t edge, irq_handler handler) {
  mcu_enter(SEAR_CALL_irq_attach_pin);
  mcu_check_pin(pin, "irq_attach_pin");
  if (!board_has_interrupt(pin))
    mcu_fatal("irq_attach_pin(%u): the ATmega2560 board has pin interrupts on 2, 3, 18..21, 10..15, 50..53 and A8..A15", pin);
  if (edge < IRQ_RISING || edge > IRQ_CHANGE) mcu_fatal("irq_attach_pin(%u, %u): edge must be IRQ_RISING, IRQ_FALLING or IRQ_CHANGE", pin, edge);
  sear_mcu.pin_handler[pin] = handler;
  sear_mcu.pin_edges[pin] = edge;
  mcu_watch_idle_loops();
  sear_mcu.pin_pending[pin] = 0;
}

void irq_detach_pin(uint8_t pin) {
  mcu_enter(SEAR_CALL_irq_detach_pin);
  mcu_check_pin(pin, "irq_detach_pin");
  sear_mcu.pin_handler[pin] = NULL;
  sear_mcu.pin_pending[pin] = 0;
}

void irq_timer_start(uint32_t period_us, irq_handler handler) {
  const int64_t now = mcu_enter(SEAR_CALL_irq_timer_start);
  if (period_us < 16 || period_us > 4194304) mcu_fatal("irq_timer_start(%lu): the period must be 16..4194304 us", (unsigned long)period_us);
  sear_mcu.timer_handler = handler;
  sear_mcu.timer_period_ns = (int64_t)period_us * 1000;
  mcu_watch_idle_loops();
  sear_mcu.timer_due_ns = now + sear_mcu.timer_period_ns;
  sear_mcu.timer_pending = 0;
  mcu_reschedule();
}

void irq_timer_stop(void) {
  mcu_enter(SEAR_CALL_irq_timer_stop);
  sear_mcu.timer_handler = NULL;
  sear_mcu.timer_pending = 0;
  mcu_reschedule();
}

void irq_attach_uart_rx(uint8_t port, irq_byte_handler handler) {
  mcu_enter(SEAR_CALL_irq_attach_uart_rx);
  if (port >= HAL_UART_COUNT) mcu_fatal("irq_attach_uart_rx(%u): the ATmega2560 has UARTs 0..3", port);
  sear_mcu.uart[port].rx_handler = handler;
  mcu_watch_idle_loops();
}

void irq_disable(void) {
  mcu_enter(SEAR_CALL_irq_disable);
  sear_mcu.irq_enabled = 0;
  mcu_reschedule();
}

void irq_enable(void) {
  mcu_enter(SEAR_CALL_irq_enable);
  sear_mcu.irq_enabled = 1;
  mcu_reschedule();
  /* Anything pending runs now, before the caller goes on, as after SEI on the chip. */
  if (sear_mcu.link->clock_ns >= sear_mcu.next_due_ns) mcu_service();
}
