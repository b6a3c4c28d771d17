/* A firmware waiting for an interrupt in a loop that makes no HAL call, such as
 * `while (!flag) {}` with `flag` set by a handler: its clock would never move, so the interrupt
 * would never come. Every few milliseconds of the process's own CPU time a signal checks for that:
 * no HAL call since the last check while an interrupt is armed means the loop can only be waiting
 * for one, so time moves on to the next interrupt, as the chip would spin until it. */
#define _GNU_SOURCE
#include <signal.h>
#include <stddef.h>
#include <sys/time.h>

#include "mcu.h"

/* CPU time, not host time: a busy host does not make a loop look idle. An AVR firmware does in
 * microseconds what it does between HAL calls, so this much CPU without one is no computation. */
#define CHECK_EVERY_US 2000

static uint64_t seen_calls;
static int64_t seen_clock;

static int interrupt_armed(void) {
  if (sear_mcu.timer_handler) return 1;
  for (int pin = 0; pin < SEAR_LINK_PINS; ++pin)
    if (sear_mcu.pin_handler[pin]) return 1;
  for (int port = 0; port < SEAR_LINK_UARTS; ++port)
    if (sear_mcu.uart[port].rx_handler) return 1;
  return 0;
}

static void on_cpu_tick(int signal_number) {
  (void)signal_number;
  struct sear_link *link = sear_mcu.link;
  const int moved = link->calls != seen_calls || link->clock_ns != seen_clock;
  seen_calls = link->calls;
  seen_clock = link->clock_ns;
  if (moved || sear_mcu.slow_path || sear_mcu.in_isr || sear_mcu.exiting || !sear_mcu.irq_enabled ||
      !interrupt_armed())
    return;
  /* Runs the lockstep from here, as an interrupt preempts the loop, until a handler has run. */
  const uint64_t handled = sear_mcu.handlers_run;
  while (sear_mcu.handlers_run == handled && !sear_mcu.exiting) {
    int64_t next = mcu_earliest_input();
    if (next > link->quantum_end_ns) next = link->quantum_end_ns;
    if (next > link->clock_ns) link->clock_ns = next;
    mcu_service();
  }
  /* The tick that fell due meanwhile arrives as soon as this returns, before the loop has looked
   * at its flag: it must not count as idle. */
  seen_calls = ~link->calls;
}

void mcu_watch_idle_loops(void) {
  struct sigaction action;
  action.sa_handler = on_cpu_tick;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGVTALRM, &action, NULL);
  const struct itimerval every = {{0, CHECK_EVERY_US}, {0, CHECK_EVERY_US}};
  setitimer(ITIMER_VIRTUAL, &every, NULL);
}
