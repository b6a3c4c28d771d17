/* The simulated MCU's state inside the firmware's process: its clock's bookkeeping, pins, inputs,
 * UARTs and interrupt sources. Data only; every layer of the runtime reads it. */
#ifndef SEAR_HAL_RUNTIME_MCU_STATE_H
#define SEAR_HAL_RUNTIME_MCU_STATE_H

#include <hal/can.h>
#include <hal/irq.h>
#include <hal/uart.h>
#include <stdint.h>

#include "devices.h" /* the device entries' constants; their state lives in devices.c */
#include "lockstep_link.h"

#define MCU_ARRIVALS 2048     /* received bytes not yet due, per port: a 10 ms quantum at 2 Mbaud */

struct mcu_arrival {
  int64_t time_ns;
  uint8_t byte;
};

struct mcu_uart {
  uint32_t baud; /* 0: not begun */
  /* Bytes leave back to back from `anchor_ns`: byte n of a burst ends at anchor + n*10/baud,
   * computed from the anchor each time so that rounding never accumulates. */
  int64_t anchor_ns;
  uint64_t burst;
  int64_t last_end_ns;
  uint8_t rx[HAL_UART_BUFFER];
  uint8_t rx_head;
  uint8_t rx_count;
  uint32_t rx_overruns;
  irq_byte_handler rx_handler;
  struct mcu_arrival arrivals[MCU_ARRIVALS]; /* ring, in time order */
  uint32_t arrival_head;
  uint32_t arrival_count;
  uint8_t handler_bytes[HAL_UART_BUFFER]; /* received, waiting for their interrupt */
  uint8_t handler_head;
  uint8_t handler_count;
  /* While interrupts are held off, received bytes wait in the USART's own two-byte FIFO, as on
   * the chip; a third is an overrun. The RX interrupt moves them on once it can run. */
  uint8_t fifo[2];
  uint8_t fifo_count;
};

#define MCU_CAN_ARRIVALS SEAR_LINK_MAX_CAN /* records not yet due: one quantum's worth */

/* The CAN controller as hal/can.h describes it (an MCP2515's buffers, filters and counters). */
struct mcu_can {
  uint32_t bitrate; /* 0: not begun */
  uint8_t tx_pending;
  struct can_frame rx[CAN_RX_BUFFERS]; /* a FIFO, oldest at rx_head */
  uint8_t rx_head;
  uint8_t rx_count;
  uint16_t rx_overruns;
  uint8_t tec;
  uint8_t rec;
  int filtering; /* from the first can_set_mask/can_set_filter after can_begin */
  uint32_t mask[2];
  uint32_t filter_id[CAN_FILTERS];
  uint8_t filter_extended[CAN_FILTERS];
  irq_handler rx_handler;
  int rx_pending; /* a kept frame waits for its interrupt */
  struct sear_link_can arrivals[MCU_CAN_ARRIVALS]; /* ring, in time order */
  uint32_t arrival_head;
  uint32_t arrival_count;
};

struct mcu {
  struct sear_link *link;
  int64_t cost_ns;
  int64_t next_due_ns; /* the earliest time anything needs the slow path */
  int irq_enabled;
  int in_isr;
  int exiting; /* after exit(): the HAL keeps answering but no longer hands over */
  int hal_ready; /* hal_init() was called: before it, every other HAL call is refused */
  /* Read by the idle-loop check's signal handler (idle.c), hence volatile. */
  volatile int slow_path;          /* inside mcu_service() or a hand-over, which may take a while */
  volatile uint64_t handlers_run;  /* interrupt handlers run so far */

  uint32_t sample_next; /* into link->samples for the current quantum */
  double analog_v[SEAR_LINK_ADC_CHANNELS];

  uint8_t mode[SEAR_LINK_PINS];
  uint8_t latch[SEAR_LINK_PINS];   /* the level the firmware drives when the pin is an output */
  uint8_t driven[SEAR_LINK_PINS];  /* the level a device drives onto the pin, or MCU_FLOATING */
  uint8_t pwm[SEAR_LINK_PINS];     /* 1 while a PWM waveform drives the pin */
  uint8_t ever_output[SEAR_LINK_PINS]; /* 1 once pin_mode() made it an OUTPUT */
  irq_handler pin_handler[SEAR_LINK_PINS];
  uint8_t pin_edges[SEAR_LINK_PINS];
  /* Pin interrupts raised and not yet delivered, bit n for pin n (pins.h): looking for one is a
   * test of two words, where a scan of 70 flags on every delivery and rescheduling was a tenth of
   * the reference rover's firmware time (1000 of them a millisecond with its LIDAR streaming). */
  uint64_t pins_pending[2];
  /* When the level a device drives last changed the pin's level: the edge's own time, which a
   * soft UART's receiver decodes from (as the chip would time it by its pin-change interrupt). */
  int64_t pin_change_ns[SEAR_LINK_PINS];

  irq_handler timer_handler;
  int64_t timer_period_ns;
  int64_t timer_due_ns;
  int timer_pending;

  uint8_t adc_reference;
  uint8_t adc_bits;

  struct mcu_uart uart[SEAR_LINK_UARTS];

  struct mcu_can can;

  uint32_t spi_clock_hz;
  uint32_t i2c_clock_hz;
};

extern struct mcu sear_mcu;

#endif
