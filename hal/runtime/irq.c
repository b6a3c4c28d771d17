/* Interrupt sources and the global enable: handlers are recorded here and run by the scheduler
 * at the first HAL call after their cause falls due. */
#include <hal/gpio.h>
#include <hal/irq.h>
#include <stddef.h>

#include "board.h"
#include "mcu.h"

/* ---- Level interrupts (IRQ_LOW) on INT0..INT5 ----
 * The pins' pending logic knows edges only: a level interrupt is registered as a falling edge,
 * and a trampoline per line raises it again after its handler while the pin is still LOW. Each
 * round costs a HAL call's time, as the chip's entry, RETI and one instruction of the main
 * program between two rounds cost cycles, so a handler that never clears its cause slows the
 * firmware to a crawl instead of stopping its clock. */

static const uint8_t level_pins[6] = {21, 20, 19, 18, 2, 3}; /* INT0..INT5 */
static irq_handler level_handlers[6];
static const irq_handler level_trampolines[6];

static void level_round(int line) {
  const uint8_t pin = level_pins[line];
  level_handlers[line]();
  if (sear_mcu.pin_handler[pin] == level_trampolines[line] && mcu_pin_level(pin) == LOW) {
    mcu_set_pin_pending(pin, 1);
    sear_mcu.link->clock_ns += sear_mcu.cost_ns;
  }
}

static void level_int0(void) { level_round(0); }
static void level_int1(void) { level_round(1); }
static void level_int2(void) { level_round(2); }
static void level_int3(void) { level_round(3); }
static void level_int4(void) { level_round(4); }
static void level_int5(void) { level_round(5); }
static const irq_handler level_trampolines[6] = {level_int0, level_int1, level_int2, level_int3, level_int4, level_int5};

static int level_line(uint8_t pin) {
  for (int line = 0; line < 6; ++line)
    if (level_pins[line] == pin) return line;
  return -1;
}

void irq_attach_pin(uint8_t pin, uint8_t edge, irq_handler handler) {
  mcu_enter(SEAR_CALL_irq_attach_pin);
  mcu_check_pin(pin, "irq_attach_pin");
  if (!board_has_interrupt(pin))
    mcu_fatal("irq_attach_pin(%u): the ATmega2560 board has pin interrupts on 2, 3, 18..21, 10..15, 50..53 and A8..A15", pin);
  if (edge < IRQ_RISING || edge > IRQ_LOW)
    mcu_fatal("irq_attach_pin(%u, %u): edge must be IRQ_RISING, IRQ_FALLING, IRQ_CHANGE or IRQ_LOW", pin, edge);
  if (handler) sear_mcu.link->usage.pin_read[pin] = 1;
  const int line = level_line(pin);
  if (edge == IRQ_LOW && line < 0)
    mcu_fatal("irq_attach_pin(%u, IRQ_LOW): level interrupts exist only on the external interrupt pins 2, 3, 18..21", pin);
  if (edge == IRQ_LOW && handler) {
    level_handlers[line] = handler;
    sear_mcu.pin_handler[pin] = level_trampolines[line];
    sear_mcu.pin_edges[pin] = IRQ_FALLING;
  } else {
    sear_mcu.pin_handler[pin] = handler;
    sear_mcu.pin_edges[pin] = edge;
  }
  mcu_watch_idle_loops();
  /* A level interrupt is due at once on a pin already LOW; an edge one waits for its edge. */
  mcu_set_pin_pending(pin, edge == IRQ_LOW && handler && mcu_pin_level(pin) == LOW);
  mcu_reschedule();
  /* ... and runs before the caller goes on, as on the chip once the mask bit is set. */
  if (mcu_pin_pending(pin) && sear_mcu.link->clock_ns >= sear_mcu.next_due_ns) mcu_service();
}

void irq_detach_pin(uint8_t pin) {
  mcu_enter(SEAR_CALL_irq_detach_pin);
  mcu_check_pin(pin, "irq_detach_pin");
  sear_mcu.pin_handler[pin] = NULL;
  mcu_set_pin_pending(pin, 0);
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
