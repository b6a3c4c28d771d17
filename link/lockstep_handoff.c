/* Spin, yield, then sleep: the hand-off of the lockstep turn (see lockstep_handoff.h). */
#define _GNU_SOURCE
#include "lockstep_handoff.h"

#include <errno.h>
#include <linux/futex.h>
#include <sched.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

static int64_t monotonic_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

#define SPIN_PAUSES 48

static void cpu_relax(void) {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

/* A process that may run on one CPU only (`taskset -c 0`, a one-core container) gains nothing by
 * spinning: the peer it waits for cannot run until it yields. The PAUSEs were 6 % of a one-core
 * reference rover's time. Asked once per process (a later change of affinity is not seen). */
unsigned sear_handoff_spin_pauses(void) {
  static int pauses = -1;
  int n = __atomic_load_n(&pauses, __ATOMIC_RELAXED);
  if (n < 0) {
    cpu_set_t cpus;
    n = sched_getaffinity(0, sizeof cpus, &cpus) == 0 && CPU_COUNT(&cpus) == 1 ? 0 : SPIN_PAUSES;
    __atomic_store_n(&pauses, n, __ATOMIC_RELAXED);
  }
  return (unsigned)n;
}

/* Not FUTEX_PRIVATE: the word lives in memory shared between two processes. */
static long futex(uint32_t *word, int op, uint32_t value, const struct timespec *timeout) {
  return syscall(SYS_futex, word, op, value, timeout, NULL, 0);
}

void sear_handoff_give(uint32_t *turn, uint32_t value, uint32_t *peer_waiting) {
  const int saved_errno = errno;
  __atomic_store_n(turn, value, __ATOMIC_SEQ_CST);
  /* Sequentially consistent on both sides: either the peer sees the new turn before sleeping,
   * or we see its waiting flag here and wake it. */
  if (__atomic_load_n(peer_waiting, __ATOMIC_SEQ_CST)) futex(turn, FUTEX_WAKE, 1, NULL);
  errno = saved_errno;
}

static int wait_for(uint32_t *turn, uint32_t value, uint32_t *self_waiting, int64_t spin_ns, int64_t timeout_ns);

/* errno is left as it was: a firmware's code may read it (the C library's free() keeps it in its
 * frame), and whether a futex wait was interrupted (EINTR), found the turn already given (EAGAIN)
 * or ran out (ETIMEDOUT) is the host's timing, which must not reach what the firmware sees. */
int sear_handoff_wait(uint32_t *turn, uint32_t value, uint32_t *self_waiting, int64_t spin_ns,
                      int64_t timeout_ns) {
  const int saved_errno = errno;
  const int taken = wait_for(turn, value, self_waiting, spin_ns, timeout_ns);
  errno = saved_errno;
  return taken;
}

static int wait_for(uint32_t *turn, uint32_t value, uint32_t *self_waiting, int64_t spin_ns, int64_t timeout_ns) {
  if (__atomic_load_n(turn, __ATOMIC_ACQUIRE) == value) return 1;
  const int64_t start = monotonic_ns();
  const unsigned pauses = sear_handoff_spin_pauses();
  /* A few dozen PAUSEs (about a microsecond) catch a peer that runs on the other core and answers
   * at once; after that, yielding lets a peer that shares this core run. Spinning longer before
   * the first yield starves exactly that peer as soon as processes outnumber cores: 4096 PAUSEs
   * (~100 us) cut two MCUs on two cores to 4x real time, against 20x with yields this early. */
  for (unsigned i = 1;; ++i) {
    if (__atomic_load_n(turn, __ATOMIC_ACQUIRE) == value) return 1;
    if (i < pauses) {
      cpu_relax();
      continue;
    }
    sched_yield();
    if ((i & 15) == 0 && monotonic_ns() - start > spin_ns) break;
  }
  for (;;) {
    const uint32_t seen = __atomic_load_n(turn, __ATOMIC_SEQ_CST);
    if (seen == value) return 1;
    int64_t left = 0;
    if (timeout_ns >= 0) {
      left = timeout_ns - (monotonic_ns() - start);
      if (left <= 0) return 0;
    }
    __atomic_store_n(self_waiting, 1, __ATOMIC_SEQ_CST);
    if (__atomic_load_n(turn, __ATOMIC_SEQ_CST) == seen) {
      struct timespec ts = {(time_t)(left / 1000000000), (long)(left % 1000000000)};
      futex(turn, FUTEX_WAIT, seen, timeout_ns >= 0 ? &ts : NULL);
    }
    __atomic_store_n(self_waiting, 0, __ATOMIC_SEQ_CST);
  }
}
