/* Interrupts: a pin's edges, one periodic timer, and each UART's received bytes. Handlers run
 * with interrupts disabled and should be short. Interrupts are enabled by hal_init(). */
#ifndef SEAR_HAL_IRQ_H
#define SEAR_HAL_IRQ_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define IRQ_RISING 1
#define IRQ_FALLING 2
#define IRQ_CHANGE 3
/* Level: the handler runs again and again as long as the pin stays LOW (external interrupt pins
 * 2, 3 and 18..21 only, as INT0..INT5's sense control allows). */
#define IRQ_LOW 4

typedef void (*irq_handler)(void);
typedef void (*irq_byte_handler)(uint8_t byte);

/* Pins 2, 3, 18, 19, 20, 21 (external interrupts) and 10..15, 50..53, A8..A15 (pin change);
 * edge IRQ_RISING, IRQ_FALLING, IRQ_CHANGE or (external pins) IRQ_LOW. */
void irq_attach_pin(uint8_t pin, uint8_t edge, irq_handler handler);
void irq_detach_pin(uint8_t pin);

/* handler runs every period_us microseconds (at least 16, at most 4194304). */
void irq_timer_start(uint32_t period_us, irq_handler handler);
void irq_timer_stop(void);

/* Each received byte goes to handler instead of the receive buffer; NULL restores the buffer. */
void irq_attach_uart_rx(uint8_t port, irq_byte_handler handler);

void irq_disable(void);
void irq_enable(void);

#ifdef __cplusplus
}
#endif
#endif
