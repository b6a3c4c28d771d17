/* When things happen in the firmware's virtual time: quantum hand-overs, sensor samples and
 * received bytes falling due, and interrupts delivered at the first HAL call after they do; and
 * the MCU's start-up, before the firmware's main(). */
#include "scheduler.h"

#include <stdio.h>

#include "can_controller.h"
#include "devices.h"
#include "link_end.h"
#include "pins.h"
#include "readings.h"

void mcu_uart_arrive(uint8_t port, uint8_t byte, int64_t time_ns) {
  struct mcu_uart *u = &sear_mcu.uart[port];
  if (u->arrival_count == MCU_ARRIVALS) {
    u->rx_overruns++;
    return;
  }
  struct mcu_arrival *a = &u->arrivals[(u->arrival_head + u->arrival_count++) % MCU_ARRIVALS];
  a->time_ns = time_ns;
  a->byte = byte;
}

/* Bytes the simulator queued for this quantum join each port's arrivals, still in time order. */
void mcu_take_quantum(void) {
  const struct sear_link *link = sear_mcu.link;
  sear_mcu.sample_next = 0;
  for (uint32_t i = 0; i < link->rx_count && i < SEAR_LINK_MAX_RX; ++i)
    if (link->rx[i].port < SEAR_LINK_UARTS) mcu_uart_arrive(link->rx[i].port, link->rx[i].byte, link->rx[i].time_ns);
  for (uint32_t i = 0; i < link->can_count && i < SEAR_LINK_MAX_CAN; ++i) mcu_can_arrive(&link->can[i]);
}

static int64_t earliest_can(void) {
  const struct mcu_can *c = &sear_mcu.can;
  return c->arrival_count ? c->arrivals[c->arrival_head].time_ns : MCU_TIME_NEVER;
}

static int64_t earliest_arrival(void) {
  int64_t t = MCU_TIME_NEVER;
  for (int port = 0; port < SEAR_LINK_UARTS; ++port) {
    const struct mcu_uart *u = &sear_mcu.uart[port];
    if (u->arrival_count && u->arrivals[u->arrival_head].time_ns < t) t = u->arrivals[u->arrival_head].time_ns;
  }
  return t;
}

static int64_t earliest_input(void) {
  const struct sear_link *link = sear_mcu.link;
  int64_t t = MCU_TIME_NEVER;
  if (sear_mcu.sample_next < link->sample_count) t = link->samples[sear_mcu.sample_next].time_ns;
  const int64_t a = earliest_arrival();
  if (a < t) t = a;
  if (sear_mcu.timer_handler && sear_mcu.timer_due_ns < t) t = sear_mcu.timer_due_ns;
  const int64_t d = mcu_devices_next_event();
  if (d < t) t = d;
  const int64_t c = earliest_can();
  if (c < t) t = c;
  return t;
}

static int interrupt_pending(void) {
  if (sear_mcu.timer_pending || sear_mcu.can.rx_pending) return 1;
  for (int port = 0; port < SEAR_LINK_UARTS; ++port)
    if (sear_mcu.uart[port].handler_count || sear_mcu.uart[port].fifo_count) return 1;
  return mcu_first_pending_pin() >= 0;
}

/* An interrupt is pending and would run at the next look: interrupts on, no handler running. */
static int interrupt_waits(void) { return sear_mcu.irq_enabled && !sear_mcu.in_isr && interrupt_pending(); }

void mcu_reschedule(void) {
  int64_t t = sear_mcu.link->quantum_end_ns;
  const int64_t input = earliest_input();
  if (input < t) t = input;
  if (interrupt_waits()) t = 0;
  sear_mcu.next_due_ns = t;
}

/* What the chip's RX interrupt does with a byte: hand it to the attached handler (later, in
 * vector order) or put it in the receive ring. */
static void receive(struct mcu_uart *u, uint8_t byte) {
  if (u->rx_handler) {
    if (u->handler_count < HAL_UART_BUFFER)
      u->handler_bytes[(uint8_t)(u->handler_head + u->handler_count++) % HAL_UART_BUFFER] = byte;
    else
      u->rx_overruns++;
  } else if (u->rx_count < HAL_UART_BUFFER) {
    u->rx[(uint8_t)(u->rx_head + u->rx_count++) % HAL_UART_BUFFER] = byte;
  } else {
    u->rx_overruns++;
  }
}

static void take_arrival(struct mcu_uart *u, uint8_t port) {
  const struct mcu_arrival a = u->arrivals[u->arrival_head];
  u->arrival_head = (u->arrival_head + 1) % MCU_ARRIVALS;
  u->arrival_count--;
  if (!u->baud) return; /* the receiver is off until uart_begin(), as on the chip */
  mcu_emit(SEAR_EVENT_UART_RX, port, a.byte, a.time_ns);
  if (!sear_mcu.irq_enabled || sear_mcu.in_isr) {
    if (u->fifo_count < sizeof u->fifo) u->fifo[u->fifo_count++] = a.byte;
    else u->rx_overruns++;
    return;
  }
  /* Older bytes still in the FIFO go first, as the chip reads them out in order. */
  for (uint8_t i = 0; i < u->fifo_count; ++i) receive(u, u->fifo[i]);
  u->fifo_count = 0;
  receive(u, a.byte);
}

/* Applies every sample, byte and timer tick due by `now`, oldest first. */
static void apply_due(int64_t now) {
  const struct sear_link *link = sear_mcu.link;
  for (;;) {
    int64_t t = MCU_TIME_NEVER;
    /* 0 sample, 1 timer, 2 + port: arrival, 2 + SEAR_LINK_UARTS: a device's event, 3 +
     * SEAR_LINK_UARTS: a CAN record */
    int which = -1;
    if (sear_mcu.sample_next < link->sample_count) {
      t = link->samples[sear_mcu.sample_next].time_ns;
      which = 0;
    }
    if (sear_mcu.timer_handler && sear_mcu.timer_due_ns < t) {
      t = sear_mcu.timer_due_ns;
      which = 1;
    }
    for (int port = 0; port < SEAR_LINK_UARTS; ++port) {
      const struct mcu_uart *u = &sear_mcu.uart[port];
      if (u->arrival_count && u->arrivals[u->arrival_head].time_ns < t) {
        t = u->arrivals[u->arrival_head].time_ns;
        which = 2 + port;
      }
    }
    const int64_t device = mcu_devices_next_event();
    if (device < t) {
      t = device;
      which = 2 + SEAR_LINK_UARTS;
    }
    if (earliest_can() < t) {
      t = earliest_can();
      which = 3 + SEAR_LINK_UARTS;
    }
    if (which < 0 || t > now) return;
    if (which == 0) {
      mcu_devices_sample(&link->samples[sear_mcu.sample_next++]);
    } else if (which == 2 + SEAR_LINK_UARTS) {
      mcu_devices_run_due(t);
    } else if (which == 3 + SEAR_LINK_UARTS) {
      struct mcu_can *c = &sear_mcu.can;
      const struct sear_link_can record = c->arrivals[c->arrival_head];
      c->arrival_head = (c->arrival_head + 1) % MCU_CAN_ARRIVALS;
      c->arrival_count--;
      mcu_can_apply(&record);
    } else if (which == 1) {
      /* One pending flag, as in the timer's hardware: ticks missed meanwhile are lost. */
      sear_mcu.timer_pending = 1;
      sear_mcu.timer_due_ns += sear_mcu.timer_period_ns;
    } else {
      take_arrival(&sear_mcu.uart[which - 2], (uint8_t)(which - 2));
    }
  }
}

/* Interrupts are off while a handler runs and on again after it, whatever it did with them, as
 * the chip's RETI sets the I flag. */
static void run_isr(irq_handler handler) {
  sear_mcu.handlers_run++;
  sear_mcu.in_isr = 1;
  handler();
  sear_mcu.in_isr = 0;
  sear_mcu.irq_enabled = 1;
}

/* In the chip's vector order: external and pin-change interrupts (the CAN controller's INT line
 * is one, after the pins'), then the timer, then UARTs. */
static int deliver_one(void) {
  const int pin = mcu_first_pending_pin();
  if (pin >= 0) {
    mcu_set_pin_pending((uint8_t)pin, 0);
    if (sear_mcu.pin_handler[pin]) run_isr(sear_mcu.pin_handler[pin]);
    return 1;
  }
  if (sear_mcu.can.rx_pending) {
    sear_mcu.can.rx_pending = 0;
    if (sear_mcu.can.rx_handler) run_isr(sear_mcu.can.rx_handler);
    return 1;
  }
  if (sear_mcu.timer_pending) {
    sear_mcu.timer_pending = 0;
    if (sear_mcu.timer_handler) run_isr(sear_mcu.timer_handler);
    return 1;
  }
  for (int port = 0; port < SEAR_LINK_UARTS; ++port) {
    struct mcu_uart *u = &sear_mcu.uart[port];
    if (u->fifo_count) {
      for (uint8_t i = 0; i < u->fifo_count; ++i) receive(u, u->fifo[i]);
      u->fifo_count = 0;
      return 1;
    }
    if (u->handler_count) {
      const uint8_t byte = u->handler_bytes[u->handler_head];
      u->handler_head = (uint8_t)((u->handler_head + 1) % HAL_UART_BUFFER);
      u->handler_count--;
      if (u->rx_handler) {
        sear_mcu.handlers_run++;
        sear_mcu.in_isr = 1;
        u->rx_handler(byte);
        sear_mcu.in_isr = 0;
        sear_mcu.irq_enabled = 1;
      } else {
        receive(u, byte); /* the handler was detached meanwhile: the ring takes it */
      }
      return 1;
    }
  }
  return 0;
}

int64_t mcu_earliest_input(void) { return earliest_input(); }

void mcu_service(void) {
  struct sear_link *link = sear_mcu.link;
  if (sear_mcu.exiting) return;
  sear_mcu.slow_path++;
  for (;;) {
    apply_due(link->clock_ns < link->quantum_end_ns ? link->clock_ns : link->quantum_end_ns - 1);
    if (link->clock_ns >= link->quantum_end_ns) {
      mcu_readings_publish();
      mcu_link_exchange();
      mcu_take_quantum();
      continue;
    }
    if (!(sear_mcu.irq_enabled && !sear_mcu.in_isr && deliver_one())) break;
  }
  mcu_reschedule();
  sear_mcu.slow_path--;
}

void mcu_advance_to(int64_t t_ns) {
  struct sear_link *link = sear_mcu.link;
  /* Exiting, or nothing falls due up to t_ns and no interrupt waits: the loop below would only
   * move the clock there (next_due_ns is never later than what next needs the slow path, as every
   * HAL call trusts). An SPI byte or an ADC conversion mostly ends so, and the loop's two looks at
   * every input cost the MPU-6000's burst a third of its time. */
  if (sear_mcu.exiting ||
      (link->clock_ns < sear_mcu.next_due_ns && t_ns < sear_mcu.next_due_ns && !interrupt_waits())) {
    if (t_ns > link->clock_ns) link->clock_ns = t_ns;
    return;
  }
  sear_mcu.slow_path++;
  for (;;) {
    mcu_service();
    if (link->clock_ns >= t_ns) break;
    int64_t next = earliest_input();
    if (t_ns < next) next = t_ns;
    if (next > link->quantum_end_ns) next = link->quantum_end_ns;
    if (next > link->clock_ns) link->clock_ns = next;
  }
  sear_mcu.slow_path--;
}

/* Start-up of the simulated MCU, before the firmware's main(): attach to the link, reset the chip's
 * state, and wait for the first quantum. It lives here, in the file every HAL call pulls in from
 * the static library, so that the linker never leaves it out. Priority 101 runs it before the
 * firmware's own constructors (default priority), so that one that calls the HAL finds it ready. */
__attribute__((constructor(101))) static void start_mcu(void) {
  /* Whatever the firmware prints on its own stdout reaches its host log at once, so that output
   * before a crash is not lost in a buffer. */
  setvbuf(stdout, NULL, _IONBF, 0);
  mcu_link_attach();
  const struct sear_link *link = sear_mcu.link;
  sear_mcu.cost_ns = link->hal_call_cost_ns;
  sear_mcu.link->usage.usage_kept = 1;
  sear_mcu.adc_bits = 10;
  for (int pin = 0; pin < SEAR_LINK_PINS; ++pin) sear_mcu.driven[pin] = MCU_FLOATING;
  /* The devices start within the first turn, so that the levels they drive at once reach the
   * simulator with that turn's events. */
  mcu_link_first_turn();
  mcu_devices_init(sear_mcu.link);
  mcu_take_quantum();
  mcu_reschedule();
}
