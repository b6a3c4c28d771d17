/* A firmware waiting for an interrupt in a loop that makes no HAL call, such as
 * `while (!flag) {}` with `flag` set by a handler: its clock would never move, so the interrupt
 * would never come. A timer signal looks at the interrupted loop every 500 us: when four looks in
 * a row, with the process running in between, find no HAL call and the same registers at the same
 * place, the loop changes nothing and can only be waiting, so time moves on to the next interrupt, as the chip would spin until it. A loop
 * that computes changes its registers, so it is never taken for one that waits. */
#define _GNU_SOURCE
#include <errno.h>
#include <signal.h>
#include <stddef.h>
#include <string.h>
#include <time.h>
#include <ucontext.h>

#include "mcu.h"

#define CHECK_EVERY_NS 500000
/* Looks in a row that must agree. One pair can agree by accident of scheduling; four running
 * ones that find the loop at the same step cannot, while it computes. */
#define LOOKS_AGREEING 4
#define MAX_WAIT_NS 100000000

/* What a spinning loop leaves unchanged: its registers, bar the instruction pointer, which may
 * stand anywhere in the loop's few instructions, and the flags its test sets. */
struct loop_state {
  int valid;
  uint64_t calls;
  int64_t clock;
  uintptr_t where;
  greg_t registers[NGREG];
};

static struct loop_state last;
static int agreeing;
/* The process's CPU time when the last look ended. The loop must have run in between: a process
 * that was not scheduled, or a look that follows the last at once, as a signal that fell due
 * during it does, shows the same registers without the loop having taken a single step. */
static int64_t last_look_ended_cpu_ns;

static int64_t cpu_ns(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (int64_t)t.tv_sec * 1000000000 + t.tv_nsec;
}

static int interrupt_armed(void) {
  if (sear_mcu.timer_handler) return 1;
  for (int pin = 0; pin < SEAR_LINK_PINS; ++pin)
    if (sear_mcu.pin_handler[pin]) return 1;
  for (int port = 0; port < SEAR_LINK_UARTS; ++port)
    if (sear_mcu.uart[port].rx_handler) return 1;
  return 0;
}

#if defined(__x86_64__)
static void capture(const ucontext_t *context, struct loop_state *s) {
  memcpy(s->registers, context->uc_mcontext.gregs, sizeof s->registers);
  s->where = (uintptr_t)s->registers[REG_RIP];
  s->registers[REG_RIP] = 0;
  s->registers[REG_EFL] = 0;
  s->registers[REG_ERR] = 0;
  s->registers[REG_TRAPNO] = 0;
  s->registers[REG_OLDMASK] = 0;
  s->registers[REG_CR2] = 0;
}
#define SEAR_IDLE_CHECK 1
#endif

#ifdef SEAR_IDLE_CHECK
static int same_loop(const struct loop_state *a, const struct loop_state *b) {
  const uintptr_t apart = a->where > b->where ? a->where - b->where : b->where - a->where;
  return a->valid && b->valid && a->calls == b->calls && a->clock == b->clock && apart < 64 &&
         memcmp(a->registers, b->registers, sizeof a->registers) == 0;
}

static void on_check(int signal_number, siginfo_t *info, void *context) {
  (void)signal_number;
  (void)info;
  const int saved_errno = errno;
  struct sear_link *link = sear_mcu.link;
  const int ran = cpu_ns() - last_look_ended_cpu_ns >= CHECK_EVERY_NS / 2;
  struct loop_state now = {ran, link->calls, link->clock_ns, 0, {0}};
  capture(context, &now);
  agreeing = same_loop(&now, &last) ? agreeing + 1 : 0;
  const int waiting = agreeing >= LOOKS_AGREEING - 1;
  last = now;
  if (!waiting || sear_mcu.slow_path || sear_mcu.in_isr || sear_mcu.exiting || !sear_mcu.irq_enabled ||
      !interrupt_armed()) {
    last_look_ended_cpu_ns = cpu_ns();
    errno = saved_errno;
    return;
  }
  /* Runs the lockstep from here, as an interrupt preempts the loop, until a handler has run; at
   * most MAX_WAIT_NS of sim time, so that a loop taken for waiting by mistake only loses that. */
  const uint64_t handled = sear_mcu.handlers_run;
  const int64_t until = link->clock_ns + MAX_WAIT_NS;
  while (sear_mcu.handlers_run == handled && !sear_mcu.exiting && link->clock_ns < until) {
    int64_t next = mcu_earliest_input();
    if (next > link->quantum_end_ns) next = link->quantum_end_ns;
    if (next > link->clock_ns) link->clock_ns = next;
    mcu_service();
  }
  last.valid = 0; /* the loop must show itself waiting again, from fresh looks */
  agreeing = 0;
  last_look_ended_cpu_ns = cpu_ns();
  errno = saved_errno;
}

void mcu_watch_idle_loops(void) {
  static int watching;
  if (watching) return;
  watching = 1;
  struct sigaction action;
  memset(&action, 0, sizeof action);
  action.sa_sigaction = on_check;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_SIGINFO | SA_RESTART;
  sigaction(SIGVTALRM, &action, NULL);
  /* Host time, not CPU time: CPU-time timers only fire on the kernel's tick (4 ms here). */
  struct sigevent event;
  memset(&event, 0, sizeof event);
  event.sigev_notify = SIGEV_SIGNAL;
  event.sigev_signo = SIGVTALRM;
  timer_t timer;
  if (timer_create(CLOCK_MONOTONIC, &event, &timer) != 0) return;
  const struct itimerspec every = {{0, CHECK_EVERY_NS}, {0, CHECK_EVERY_NS}};
  timer_settime(timer, 0, &every, NULL);
}
#else
/* Elsewhere a loop that waits without HAL calls is reported as hung. */
void mcu_watch_idle_loops(void) {}
#endif
