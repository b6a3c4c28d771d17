/* The idle-loop check: a firmware waiting for an interrupt in a loop that makes no HAL call, such
 * as `while (!flag) {}` with `flag` set by a handler, never moves its clock, so the interrupt would
 * never come. When the process is proven to be in such a cycle, time moves on to the next interrupt,
 * as the chip would spin until it.
 *
 * The proof, on x86-64: a timer signal looks at the interrupted firmware and takes its whole state
 * there (general registers with the flags, x87/SSE/AVX registers, and a digest of every private
 * writable mapping: the executables' .data/.bss, the heap, other anonymous memory, the stack from
 * the red zone up), then single-steps it with the trap flag. If it comes back to the same
 * instruction with every register the same, no HAL call made, no clock moved and the same memory,
 * the next pass is the same pass again, and so on for ever: nothing but an interrupt can end it.
 * A computing loop changes some register or some memory on every pass, so it is never taken for a
 * wait, whatever the host's load; a missed wait only costs speed (the next look tries again).
 *
 * What the proof does not see, and so assumes: memory the firmware shares with another process
 * (mapped MAP_SHARED, or the vDSO's clock page) and threads other than the stepped one; a cycle that
 * makes a system call or reads the time stamp counter or a random number is refused for that
 * reason, and so is a process with more than one thread. Signals of the firmware's own (a host
 * timer) could end such a loop too; an MCU firmware has none. A debugger that traps SIGTRAP sees the
 * steps. Each jump stays bounded (MAX_WAIT_NS) so that a loop outside these assumptions loses at
 * most that. Elsewhere than x86-64 such loops are reported as hung.
 *
 * A look that finds the firmware in an empty endless loop (`while (true);`, `for (;;);`: `jmp .`,
 * or `nop; jmp .-1` unoptimised) needs no proof: that loop reads nothing and changes nothing, so
 * only an interrupt can preempt it, and after the interrupt it is there again. The MCU is halted
 * from the moment it got there (its clock has not moved since): the simulator is told once, and
 * from then on the look's handler runs the lockstep itself, delivering interrupts at their times
 * while the world runs on, and never returns to the loop. */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stddef.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <time.h>
#include <ucontext.h>
#include <unistd.h>

#include "mcu.h"

#if defined(__x86_64__)
#include <cpuid.h>

/* How often to look while the firmware calls the HAL: a look then costs one signal (~4 us here). */
#define LOOK_EVERY_NS 500000
/* After a proven wait the firmware most likely waits again soon, in the same loop (a main loop
 * paced by a timer tick): look again this soon, doubling while it is elsewhere. A one-shot timer
 * armed for 20 us fires ~30 us later in these VMs, and a look that does not step costs a signal
 * (~4-10 us), while one step costs ~12 us: cheaper than stepping through whatever the firmware
 * does after the interrupt until it is back in the loop. */
#define LOOK_SOON_NS 20000
/* A look that finds a computing loop costs ~50-100 us (a few steps, the memory digest); doubling
 * the interval up to this keeps that under 3 % of a long computation. */
#define LOOK_AT_MOST_EVERY_NS 4000000
/* Instructions stepped before giving up: a waiting loop is a handful (`while (!flag) {}` is 3);
 * each step costs ~12 us of host time in these VMs. */
#define STEP_BUDGET 32
/* The longest jump at once: the proof makes a wait certain, so this bounds only what its stated
 * assumptions could not (memory shared with another process, signals of the firmware's own); it
 * costs one more look per 100 ms of simulated waiting. */
#define MAX_WAIT_NS 100000000
#define RED_ZONE 128          /* below the stack pointer, leaf functions keep data (SysV ABI) */
#define MAX_REGIONS 256
/* Digesting runs at ~25 GB/s here; beyond this much writable memory (a sanitizer's shadow, a huge
 * reservation) a look would take tens of milliseconds, so such a firmware is not looked at. */
#define MAX_DIGESTED ((uintptr_t)1 << 30)
#define MAX_FP_STATE 12288    /* the XSAVE components compared, AMX's tiles included */
#define TRAP_FLAG 0x100
#define RESUME_FLAG 0x10000
#define VSYSCALL_PAGE 0xffffffffff600000u
/* The kernel's XSAVE signal frame (asm/sigcontext.h): software bytes at 464 of the FXSAVE area,
 * then the XSAVE header at 512. */
#define FX_SW_BYTES 464
#define XSAVE_HEADER 512
#define XSTATE_MAGIC1 0x46505853u
#define XSAVE_COMPONENTS 19

struct region {
  uintptr_t start, end;
};

struct state {
  uintptr_t rip;
  greg_t registers[NGREG];
  size_t fp_size;
  unsigned char fp[MAX_FP_STATE];
};

/* Everything the check keeps lives in its own mapping, outside what it digests, so that looking
 * does not change what is looked at. */
struct watch {
  volatile int stepping;
  int steps;
  int reanchors_left;
  int soon; /* stepping soon after a wait, in the loop that waited */
  int64_t due_ns; /* when the armed look falls due */
  int64_t interval_ns;
  uint64_t calls_at_last_look;
  timer_t timer;
  /* The instructions of the loop last proven to wait, and of the cycle being stepped. */
  uintptr_t loop_low, loop_high, cycle_low, cycle_high;
  uintptr_t resumed_at; /* where the firmware went on after its last wait */
  int resumed_unseen;   /* ... and no look has found it elsewhere since */
  /* The anchor: the state the firmware must come back to. */
  uint64_t calls;
  int64_t clock;
  struct state anchor;
  struct state now;
  uint64_t digest[4];
  int region_count;
  uintptr_t region_bytes;
  struct region regions[MAX_REGIONS];
  uintptr_t vdso_start, vdso_end;
  struct {
    uint32_t offset, size;
  } component[XSAVE_COMPONENTS];
  char maps[4096];
  /* Where the check's signals run: their frames hold the interrupted registers and FP state at a
   * host-timed instant, which on the firmware's own stack an uninitialised local would read next
   * (startup_memory.c); here they are also out of what the check digests. Room for the largest
   * XSAVE frame (AMX) and the handlers' own frames. */
  _Alignas(16) unsigned char signal_stack[64 * 1024];
};

static struct watch *w;

static int interrupt_armed(void) {
  if (sear_mcu.timer_handler) return 1;
  for (int pin = 0; pin < SEAR_LINK_PINS; ++pin)
    if (sear_mcu.pin_handler[pin]) return 1;
  for (int port = 0; port < SEAR_LINK_UARTS; ++port)
    if (sear_mcu.uart[port].rx_handler) return 1;
  return 0;
}

/* Only a loop outside the HAL's slow path, with interrupts on and one that could arrive, can wait
 * for an interrupt. */
static int may_wait(void) {
  return !sear_mcu.slow_path && !sear_mcu.in_isr && !sear_mcu.exiting && sear_mcu.irq_enabled && interrupt_armed();
}

/* Instructions whose result comes from outside the compared state (a system call, the time stamp
 * counter, the random number generator): a cycle through one proves nothing. So do code in the
 * vDSO, which reads the kernel's clock page, and the vsyscall page, which cannot even be read. */
static int reads_the_host(uintptr_t rip) {
  if (rip >= VSYSCALL_PAGE || (rip >= w->vdso_start && rip < w->vdso_end)) return 1;
  const unsigned char *p = (const unsigned char *)rip;
  for (int i = 0; i < 14; ++i, ++p) { /* legacy and REX prefixes */
    const unsigned char b = *p;
    if (!(b == 0x66 || b == 0x67 || b == 0xF0 || b == 0xF2 || b == 0xF3 || b == 0x2E || b == 0x36 || b == 0x3E ||
          b == 0x26 || b == 0x64 || b == 0x65 || (b >= 0x40 && b <= 0x4F)))
      break;
  }
  if (p[0] == 0xCC || p[0] == 0xCD) return 1; /* int3, int n */
  if (p[0] != 0x0F) return 0;
  switch (p[1]) {
    case 0x05: /* syscall */
    case 0x34: /* sysenter */
    case 0x31: /* rdtsc */
    case 0x33: /* rdpmc */
      return 1;
    case 0x01:
      return p[2] == 0xF9; /* rdtscp */
    case 0xC7:
      return (p[2] & 0xC0) == 0xC0 && ((p[2] >> 3) & 7) >= 6; /* rdrand, rdseed, rdpid */
    default:
      return 0;
  }
}

/* Registers as the firmware sees them: the trap flag and resume flag are the check's own, and the
 * error code, trap number, old mask and CR2 describe the signal, not the firmware. */
static void take_registers(const ucontext_t *context, struct state *s) {
  memcpy(s->registers, context->uc_mcontext.gregs, sizeof s->registers);
  s->rip = (uintptr_t)s->registers[REG_RIP];
  s->registers[REG_EFL] &= ~(greg_t)(TRAP_FLAG | RESUME_FLAG);
  s->registers[REG_ERR] = 0;
  s->registers[REG_TRAPNO] = 0;
  s->registers[REG_OLDMASK] = 0;
  s->registers[REG_CR2] = 0;
}

static void put(struct state *s, const void *bytes, size_t n) {
  if (s->fp_size + n > sizeof s->fp) return; /* cannot happen with the components known today */
  if (bytes) memcpy(s->fp + s->fp_size, bytes, n);
  else memset(s->fp + s->fp_size, 0, n);
  s->fp_size += n;
}

/* The floating-point and vector state: x87 control, status and tag words, st0-7 (their 80 bits,
 * not the reserved bytes), MXCSR, xmm0-15, and every further XSAVE component the kernel saved
 * (AVX's upper halves, AVX-512, ...), a component in its initial state (its XSTATE_BV bit clear)
 * read as that state rather than as whatever bytes the frame holds there. The x87's
 * last-instruction pointers are left out: they describe history, not state a computation reads,
 * and AMD processors do not always save them. */
static void take_fp(const ucontext_t *context, struct state *s) {
  static const uint16_t x87_initial[3] = {0x037F, 0, 0};
  static const unsigned char zeros[10];
  s->fp_size = 0;
  const struct _libc_fpstate *fx = context->uc_mcontext.fpregs;
  if (!fx) return;
  const unsigned char *area = (const unsigned char *)fx;
  uint32_t magic, xstate_size = 0;
  uint64_t features = 0, present = 3; /* FXSAVE alone: x87 and SSE as saved */
  memcpy(&magic, area + FX_SW_BYTES, sizeof magic);
  if (magic == XSTATE_MAGIC1) {
    memcpy(&features, area + FX_SW_BYTES + 8, sizeof features);
    memcpy(&xstate_size, area + FX_SW_BYTES + 16, sizeof xstate_size);
    memcpy(&present, area + XSAVE_HEADER, sizeof present);
  }
  const uint16_t x87[3] = {fx->cwd, fx->swd, (uint16_t)(fx->ftw & 0xFF)};
  put(s, present & 1 ? x87 : x87_initial, sizeof x87);
  put(s, &fx->mxcsr, sizeof fx->mxcsr); /* saved whenever SSE or AVX is */
  for (int i = 0; i < 8; ++i) put(s, present & 1 ? (const void *)&fx->_st[i] : zeros, 10);
  put(s, present & 2 ? (const void *)fx->_xmm : NULL, sizeof fx->_xmm);
  for (int i = 2; i < XSAVE_COMPONENTS; ++i) {
    const uint32_t offset = w->component[i].offset, size = w->component[i].size;
    if (!((features >> i) & 1) || !size || offset + size > xstate_size) continue;
    put(s, (present >> i) & 1 ? area + offset : NULL, size);
  }
}

static int same_state(const struct state *a, const struct state *b) {
  return a->rip == b->rip && memcmp(a->registers, b->registers, sizeof a->registers) == 0 && a->fp_size == b->fp_size &&
         memcmp(a->fp, b->fp, a->fp_size) == 0;
}

static uintptr_t hex(const char **p) {
  uintptr_t v = 0;
  for (;; ++*p) {
    const char c = **p;
    if (c >= '0' && c <= '9') v = v * 16 + (uintptr_t)(c - '0');
    else if (c >= 'a' && c <= 'f') v = v * 16 + (uintptr_t)(c - 'a' + 10);
    else return v;
  }
}

#ifdef __SANITIZE_ADDRESS__
/* The x86-64 shadow layout: low shadow, shadow gap, high shadow. */
#define ASAN_SHADOW_START ((uintptr_t)0x00007fff8000ull)
#define ASAN_SHADOW_END ((uintptr_t)0x10007fff8000ull)
#endif

static void add_region(uintptr_t start, uintptr_t end) {
  if (w->region_count < MAX_REGIONS) w->regions[w->region_count] = (struct region){start, end};
  w->region_count++;
  w->region_bytes += end - start;
}

/* One line of /proc/self/maps: "start-end perms offset dev inode [name]". */
static void take_mapping(const char *line, uintptr_t stack_pointer) {
  const uintptr_t start = hex(&line);
  ++line;
  const uintptr_t end = hex(&line);
  ++line;
  const int private_writable = line[1] == 'w' && line[3] == 'p';
  if (strstr(line, "[vdso]")) {
    w->vdso_start = start;
    w->vdso_end = end;
  }
  if (!private_writable) return;
#ifdef __SANITIZE_ADDRESS__
  /* AddressSanitizer's shadow (terabytes reserved, for sanitizer builds of the tests) changes only
   * when memory is allocated, freed or a frame with arrays is entered: never in a loop that waits. */
  if (start >= ASAN_SHADOW_START && end <= ASAN_SHADOW_END) return;
#endif
  struct region r = {start, end};
  /* Below the red zone lies only what the firmware has let go of, and the signal frames. */
  if (stack_pointer >= start && stack_pointer < end && stack_pointer - RED_ZONE > start) r.start = stack_pointer - RED_ZONE;
  /* The kernel may have merged the check's own block with a neighbouring mapping. */
  const uintptr_t own_start = (uintptr_t)w, own_end = own_start + sizeof *w;
  if (own_start < r.end && own_end > r.start) {
    if (r.start < own_start) add_region(r.start, own_start);
    if (own_end < r.end) add_region(own_end, r.end);
  } else {
    add_region(r.start, r.end);
  }
}

/* The private writable mappings now, found with open/read only (async-signal-safe). Returns 0 if
 * the list cannot be read or does not fit, and then nothing is proven. */
static int take_regions(uintptr_t stack_pointer) {
  w->region_count = 0;
  w->region_bytes = 0;
  const int fd = open("/proc/self/maps", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  size_t kept = 0;
  int complete = 0;
  for (;;) {
    const ssize_t n = read(fd, w->maps + kept, sizeof w->maps - 1 - kept);
    if (n <= 0) {
      complete = n == 0 && kept == 0;
      break;
    }
    kept += (size_t)n;
    w->maps[kept] = '\0';
    char *line = w->maps;
    for (char *eol; (eol = strchr(line, '\n')) != NULL; line = eol + 1) {
      *eol = '\0';
      take_mapping(line, stack_pointer);
    }
    kept = (size_t)(w->maps + kept - line);
    memmove(w->maps, line, kept);
    if (kept == sizeof w->maps - 1) break; /* a line longer than the buffer */
  }
  close(fd);
  return complete && w->region_count <= MAX_REGIONS && w->region_bytes <= MAX_DIGESTED;
}

/* A digest of the regions in four independent lanes of (h ^ word) * odd constant: each step is a
 * bijection, so a change in one word always changes its lane's result, and changes in several
 * words of every lane would have to cancel exactly to go unseen. It reads every byte of the
 * firmware's memory, a sanitizer's red zones too, so it reads words directly (regions are page
 * aligned) rather than through memcpy, which a sanitizer would intercept and check. */
typedef uint64_t __attribute__((may_alias)) any_word;

__attribute__((no_sanitize_address)) static void digest_memory(uint64_t out[4]) {
  const uint64_t k = 0x9E3779B97F4A7C15u;
  uint64_t h[4] = {1, 2, 3, 4};
  for (int r = 0; r < w->region_count; ++r) {
    const unsigned char *p = (const unsigned char *)w->regions[r].start;
    const unsigned char *end = (const unsigned char *)w->regions[r].end;
    h[0] = (h[0] ^ w->regions[r].start) * k;
    h[1] = (h[1] ^ w->regions[r].end) * k;
    for (; end - p >= 32; p += 32) {
      const any_word *v = (const any_word *)(const void *)p;
      h[0] = (h[0] ^ v[0]) * k;
      h[1] = (h[1] ^ v[1]) * k;
      h[2] = (h[2] ^ v[2]) * k;
      h[3] = (h[3] ^ v[3]) * k;
    }
    for (; p < end; ++p) h[3] = (h[3] ^ *p) * k;
  }
  for (int i = 0; i < 4; ++i) out[i] = h[i];
}

static int single_threaded(void) {
  struct stat tasks;
  /* A task directory links to itself, its parent and each thread. */
  return stat("/proc/self/task", &tasks) == 0 && tasks.st_nlink == 3;
}

static int64_t now_ns(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (int64_t)t.tv_sec * 1000000000 + t.tv_nsec;
}

static void arm(int64_t ns) {
  const struct itimerspec once = {{0, 0}, {ns / 1000000000, ns % 1000000000}};
  w->due_ns = now_ns() + ns;
  timer_settime(w->timer, 0, &once, NULL);
}

static void look_in(int64_t ns) {
  w->interval_ns = ns;
  arm(ns);
}

/* The firmware is calling the HAL, which moves its clock: look at the usual pace. */
static void look_later(void) { look_in(w->interval_ns >= LOOK_EVERY_NS ? LOOK_EVERY_NS : 2 * w->interval_ns); }

/* The firmware computes: look ever more rarely, so as not to slow it. */
static void look_much_later(void) {
  look_in(2 * w->interval_ns < LOOK_AT_MOST_EVERY_NS ? 2 * w->interval_ns : LOOK_AT_MOST_EVERY_NS);
}

static void stop_stepping(ucontext_t *context) {
  context->uc_mcontext.gregs[REG_EFL] &= ~(greg_t)TRAP_FLAG;
  w->stepping = 0;
}

/* Runs the lockstep from here, as an interrupt preempts the loop, until a handler has run. */
static void run_to_next_interrupt(void) {
  struct sear_link *link = sear_mcu.link;
  const uint64_t handled = sear_mcu.handlers_run;
  const int64_t until = link->clock_ns + MAX_WAIT_NS;
  while (sear_mcu.handlers_run == handled && !sear_mcu.exiting && link->clock_ns < until) {
    int64_t next = mcu_earliest_input();
    if (next > link->quantum_end_ns) next = link->quantum_end_ns;
    if (next > link->clock_ns) link->clock_ns = next;
    mcu_service();
  }
}

/* The length of the no-operation instruction at `p`, or 0 if it is something else: `nop` (90),
 * with operand-size or segment prefixes (66 90, `xchg %ax,%ax`), and the long forms
 * `nopw/nopl disp(base,index)` (0F 1F /0) compilers pad with, whose memory operand is never read. */
static int nop_length(const unsigned char *p) {
  int n = 0;
  while (n < 4 && (p[n] == 0x66 || p[n] == 0x2E || p[n] == 0x3E)) ++n;
  if (p[n] == 0x90) return n + 1; /* not F3 90 (pause) nor 4x 90 (xchg with r8), which are not listed */
  if (p[n] != 0x0F || p[n + 1] != 0x1F) return 0;
  const unsigned char modrm = p[n + 2];
  const int mod = modrm >> 6, reg = (modrm >> 3) & 7, rm = modrm & 7;
  if (reg != 0) return 0; /* 0F 1F /1../7 are reserved hints, not the documented NOP */
  n += 3;
  if (mod == 3) return n;
  if (rm == 4) { /* a SIB byte; base 5 with mod 0 means a 32-bit displacement instead of a base */
    if (mod == 0 && (p[n] & 7) == 5) n += 4;
    ++n;
  } else if (mod == 0 && rm == 5) {
    n += 4; /* rip-relative */
  }
  return n + (mod == 1 ? 1 : mod == 2 ? 4 : 0);
}

/* The longest run of no-operations before the jump that is taken for an empty loop. */
#define MAX_LOOP_NOPS 16

/* The instruction at `rip` is in an empty endless loop: from it, no-operations only lead to a jump
 * back (`jmp rel8` EB, `jmp rel32` E9) to a place from which no-operations only lead to that same
 * jump. An optimised build makes `while (true);` and `for (;;);` a jump to itself (`jmp .`); GCC
 * without optimisation (a Debug build, the sanitizers' test build) keeps a `nop` for the empty
 * body, on which a debugger can stop, and jumps back to it: `nop; jmp .-1` (90 EB FD). Either reads
 * nothing and changes nothing but the instruction pointer. A loop that does anything at all, even
 * only reads a volatile flag, has another instruction in it and is not this. */
static int in_empty_loop(uintptr_t rip) {
  if (rip >= VSYSCALL_PAGE || (rip >= w->vdso_start && rip < w->vdso_end)) return 0;
  const unsigned char *p = (const unsigned char *)rip;
  for (int len, skipped = 0; (len = nop_length(p)) > 0; p += len)
    if ((skipped += len) > MAX_LOOP_NOPS) return 0;
  const unsigned char *next;
  int32_t offset;
  if (p[0] == 0xEB) {
    next = p + 2;
    offset = (int8_t)p[1];
  } else if (p[0] == 0xE9) {
    next = p + 5;
    memcpy(&offset, p + 1, sizeof offset);
  } else {
    return 0;
  }
  const unsigned char *target = next + offset;
  if (target > p || p - target > MAX_LOOP_NOPS) return 0;
  while (target < p) {
    const int len = nop_length(target);
    if (len == 0) return 0;
    target += len;
  }
  return target == p; /* not a jump into the middle of an instruction */
}

/* The firmware sits in an empty loop for good: tells the simulator once, then runs the lockstep from
 * here for the rest of the run, as the chip would keep taking interrupts from the loop (none while
 * they are off, or inside a handler that never returns). Never returns: what it preempted would
 * only jump to itself again. Looks stop; SIGVTALRM is held while this handler runs anyway. */
static void halt_here(void) {
  struct sear_link *link = sear_mcu.link;
  const struct itimerspec never = {{0, 0}, {0, 0}};
  timer_settime(w->timer, 0, &never, NULL);
  const int interrupts_off = !sear_mcu.irq_enabled || sear_mcu.in_isr;
  link->halted_ns = link->clock_ns;
  __atomic_store_n(&link->halt, (uint32_t)(interrupts_off ? SEAR_HALT_EMPTY_LOOP_IRQ_OFF : SEAR_HALT_EMPTY_LOOP),
                   __ATOMIC_RELEASE);
  for (;;) {
    int64_t next = mcu_earliest_input();
    if (next > link->quantum_end_ns) next = link->quantum_end_ns;
    if (next > link->clock_ns) link->clock_ns = next;
    mcu_service();
  }
}

static void on_look(int signal_number, siginfo_t *info, void *untyped) {
  (void)signal_number;
  (void)info;
  const int saved_errno = errno;
  ucontext_t *context = untyped;
  struct sear_link *link = sear_mcu.link;
  /* A look that fell due while the check itself ran (signals are held then) and has since been
   * re-armed: the firmware has not run since, so it would only find the loop as it was left. */
  if (now_ns() < w->due_ns) {
    errno = saved_errno;
    return;
  }
  if (w->stepping && (context->uc_mcontext.gregs[REG_EFL] & TRAP_FLAG)) {
    arm(LOOK_EVERY_NS); /* still stepping, delayed by the host */
    errno = saved_errno;
    return;
  }
  w->stepping = 0; /* if it was on, the firmware cleared the trap flag itself (popf) */
  /* Halted, whatever it waits for: with no interrupt armed, or with interrupts off, too. A
   * firmware past exit() has let go of the link, and another thread could still call the HAL. */
  if (!sear_mcu.exiting && in_empty_loop((uintptr_t)context->uc_mcontext.gregs[REG_RIP]) && single_threaded())
    halt_here();
  const uint64_t calls = link->calls;
  const int calling = calls != w->calls_at_last_look;
  w->calls_at_last_look = calls;
  /* At the usual pace, a firmware that called the HAL since the last look is not waiting without
   * it; soon after a wait, the next wait is expected and looked for at once. */
  if ((calling && w->interval_ns >= LOOK_EVERY_NS) || !may_wait()) {
    look_later();
    errno = saved_errno;
    return;
  }
  take_registers(context, &w->anchor);
  /* Soon after a wait, only the loop that waited is worth stepping: elsewhere the firmware is
   * still on its way back to it, and stepping there costs more than a few more looks. */
  if (w->interval_ns < LOOK_EVERY_NS && (w->anchor.rip < w->loop_low || w->anchor.rip > w->loop_high)) {
    w->resumed_unseen = 0;
    look_later();
    errno = saved_errno;
    return;
  }
  /* Found just where the interrupt left it, with no HAL call since: the host has most likely not
   * run it since (a signal's return takes ~10 us here, and another process may have had its
   * core), and stepping it now would only see it leave the loop. Once is enough to tell. */
  if (w->interval_ns < LOOK_EVERY_NS && w->resumed_unseen && w->anchor.rip == w->resumed_at && !calling) {
    w->resumed_unseen = 0;
    arm(w->interval_ns);
    errno = saved_errno;
    return;
  }
  w->resumed_unseen = 0;
  if (reads_the_host(w->anchor.rip) || !take_regions((uintptr_t)w->anchor.registers[REG_RSP])) {
    look_much_later();
    errno = saved_errno;
    return;
  }
  take_fp(context, &w->anchor);
  w->calls = calls;
  w->clock = link->clock_ns;
  errno = saved_errno; /* the digest includes errno, which open() may have set */
  digest_memory(w->digest);
  w->steps = 0;
  w->soon = w->interval_ns < LOOK_EVERY_NS;
  w->reanchors_left = w->soon;
  w->cycle_low = w->cycle_high = w->anchor.rip;
  w->stepping = 1;
  context->uc_mcontext.gregs[REG_EFL] |= TRAP_FLAG;
  arm(LOOK_EVERY_NS); /* in case stepping is lost */
  errno = saved_errno;
}

static void on_step(int signal_number, siginfo_t *info, void *untyped) {
  const int saved_errno = errno;
  ucontext_t *context = untyped;
  if (!w->stepping || info->si_code != TRAP_TRACE) {
    /* Not a step of ours: what SIGTRAP does by default, once this handler returns. */
    signal(signal_number, SIG_DFL);
    raise(signal_number);
    errno = saved_errno;
    return;
  }
  struct sear_link *link = sear_mcu.link;
  ++w->steps;
  const uintptr_t rip = (uintptr_t)context->uc_mcontext.gregs[REG_RIP];
  if (rip < w->cycle_low) w->cycle_low = rip;
  if (rip > w->cycle_high) w->cycle_high = rip;
  if (link->calls != w->calls || link->clock_ns != w->clock || !may_wait()) {
    stop_stepping(context);
    look_later();
  } else if (rip == w->anchor.rip) {
    take_registers(context, &w->now);
    take_fp(context, &w->now);
    uint64_t digest[4];
    if (!same_state(&w->now, &w->anchor) && w->reanchors_left > 0 && w->steps < STEP_BUDGET &&
        w->now.registers[REG_RSP] == w->anchor.registers[REG_RSP]) {
      /* Back in the loop that waited, with what the firmware did in between still in some
       * register (the first pass overwrites it): this pass is the one to compare with. No system
       * call came in between, so the mappings are still those listed, and with the same stack
       * pointer the stack's digested part is too. */
      --w->reanchors_left;
      w->anchor = w->now;
      digest_memory(w->digest);
      errno = saved_errno;
      return;
    }
    if (same_state(&w->now, &w->anchor)) digest_memory(digest);
    stop_stepping(context);
    if (same_state(&w->now, &w->anchor) && memcmp(digest, w->digest, sizeof digest) == 0 && single_threaded()) {
      run_to_next_interrupt();
      w->loop_low = w->cycle_low;
      w->loop_high = w->cycle_high;
      w->calls_at_last_look = link->calls;
      w->resumed_at = w->now.rip;
      w->resumed_unseen = 1;
      look_in(LOOK_SOON_NS);
    } else {
      look_much_later();
    }
  } else if (w->soon && (rip < w->loop_low || rip > w->loop_high)) {
    /* Soon after a wait, the loop that waited is only now being left after its interrupt (the
     * host had not run the firmware since): look again once it is back. */
    stop_stepping(context);
    look_later();
  } else if (w->steps >= STEP_BUDGET || reads_the_host(rip)) {
    stop_stepping(context);
    look_much_later();
  }
  errno = saved_errno;
}

static void find_xsave_layout(void) {
  unsigned int max_leaf = __get_cpuid_max(0, NULL);
  if (max_leaf < 0xD) return;
  for (unsigned int i = 2; i < XSAVE_COMPONENTS; ++i) {
    unsigned int size, offset, flags, unused;
    __cpuid_count(0xD, i, size, offset, flags, unused);
    (void)unused;
    if (flags & 1) continue; /* supervisor state: never in a signal frame */
    w->component[i].offset = offset;
    w->component[i].size = size;
  }
}

void mcu_watch_idle_loops(void) {
  static int watching;
  if (watching) return;
  watching = 1;
  void *block = mmap(NULL, sizeof *w, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (block == MAP_FAILED) return;
  w = block;
  find_xsave_layout();
  /* Finds the vDSO, and calls what the check calls once, here, so that lazy binding does not
   * write the executable's GOT between an anchor and its proof (that would only cost a miss). */
  take_regions(0);
  (void)single_threaded();
  (void)same_state(&w->anchor, &w->now);
  w->interval_ns = LOOK_EVERY_NS;
  const stack_t own_stack = {.ss_sp = w->signal_stack, .ss_flags = 0, .ss_size = sizeof w->signal_stack};
  if (sigaltstack(&own_stack, NULL) != 0) return;

  struct sigaction action;
  memset(&action, 0, sizeof action);
  action.sa_sigaction = on_step;
  sigemptyset(&action.sa_mask);
  sigaddset(&action.sa_mask, SIGVTALRM);
  action.sa_flags = SA_SIGINFO | SA_RESTART | SA_ONSTACK;
  sigaction(SIGTRAP, &action, NULL);
  action.sa_sigaction = on_look;
  sigemptyset(&action.sa_mask);
  sigaction(SIGVTALRM, &action, NULL);
  /* Host time, not CPU time: CPU-time timers only fire on the kernel's tick (4 ms here). */
  struct sigevent event;
  memset(&event, 0, sizeof event);
  event.sigev_notify = SIGEV_SIGNAL;
  event.sigev_signo = SIGVTALRM;
  if (timer_create(CLOCK_MONOTONIC, &event, &w->timer) != 0) return;
  look_in(LOOK_EVERY_NS);
}
#else
/* Elsewhere a loop that waits without HAL calls is reported as hung. */
void mcu_watch_idle_loops(void) {}
#endif
