/* The firmware's end of the lockstep link (see link_end.h). */
#define _GNU_SOURCE
#include "link_end.h"
#include "startup_memory.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include "lockstep_handoff.h"
#include "mcu_state.h"

struct mcu sear_mcu;

/* Spinning this long covers a physics step with room to spare; beyond it the simulator is
 * probably busy with other MCUs, and sleeping frees the core for them. */
#define SPIN_NS 200000

static pid_t simulator;

/* Waits for the turn; a simulator that died without handing it over must not leave this process
 * waiting for ever. The parent-death signal the simulator set up kills it at once; this look,
 * once a second, is for the moment before that signal was armed. */
static void wait_for_turn(void) {
  struct sear_link *link = sear_mcu.link;
  while (!sear_handoff_wait(&link->turn, SEAR_TURN_FIRMWARE, &link->firmware_waiting, SPIN_NS, 1000000000))
    if (getppid() != simulator) _exit(3);
  mcu_paint_after_wait(); /* its dead frames hold host times */
}

static void hand_over(enum sear_request request) {
  struct sear_link *link = sear_mcu.link;
  if (sear_mcu.exiting) return; /* the simulator has let go of this MCU */
  sear_mcu.slow_path++;
  link->request = (uint32_t)request;
  sear_handoff_give(&link->turn, SEAR_TURN_SIM, &link->sim_waiting);
  wait_for_turn();
  sear_mcu.slow_path--;
}

void mcu_link_exchange(void) { hand_over(SEAR_REQUEST_QUANTUM_DONE); }

void mcu_link_first_turn(void) { wait_for_turn(); }

void mcu_emit(enum sear_event_kind kind, uint8_t index, uint32_t value, int64_t time_ns) {
  struct sear_link *link = sear_mcu.link;
  if (sear_mcu.exiting) return;
  if (link->event_count >= SEAR_LINK_MAX_EVENTS) hand_over(SEAR_REQUEST_DRAIN);
  struct sear_event *e = &link->events[link->event_count];
  e->time_ns = time_ns;
  e->value = value;
  e->kind = (uint8_t)kind;
  e->index = index;
  /* Published only once written, so a crash right after leaves no half event behind. */
  __atomic_store_n(&link->event_count, link->event_count + 1, __ATOMIC_RELEASE);
}

void mcu_fatal(const char *format, ...) {
  struct sear_link *link = sear_mcu.link;
  va_list args;
  va_start(args, format);
  vsnprintf(link->fatal, sizeof link->fatal, format, args);
  va_end(args);
  if (sear_mcu.exiting) fprintf(stderr, "sear: after exit(): %s\n", link->fatal); /* nobody reads the link now */
  link->request = SEAR_REQUEST_FATAL;
  sear_handoff_give(&link->turn, SEAR_TURN_SIM, &link->sim_waiting);
  _exit(70);
}

/* main() returned or exit() was called: tell the simulator at once rather than let it find the
 * process gone at its next check. Destructors may still call the HAL after this; from now on it
 * neither hands over nor reports, so they cannot wait for a turn that never comes. */
static void at_exit(void) {
  /* Later calls work on a private copy, so the report keeps the clock and the call at exit. */
  static struct sear_link after_exit;
  struct sear_link *link = sear_mcu.link;
  after_exit = *link;
  sear_mcu.link = &after_exit;
  sear_mcu.exiting = 1;
  link->request = SEAR_REQUEST_EXIT;
  sear_handoff_give(&link->turn, SEAR_TURN_SIM, &link->sim_waiting);
}

void mcu_link_attach(void) {
  const char *fd_text = getenv(SEAR_LINK_FD_ENV);
  if (!fd_text) {
    fprintf(stderr, "This firmware was built for the SEAR simulator: run it through a project, "
                    "with `sear run PROJECT`.\n");
    _exit(2);
  }
  const int fd = atoi(fd_text);
  void *page = mmap(NULL, sizeof(struct sear_link), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  if (page == MAP_FAILED) {
    perror("sear: mapping the lockstep link");
    _exit(2);
  }
  close(fd);
  struct sear_link *link = page;
  if (link->magic != SEAR_LINK_MAGIC || link->version != SEAR_LINK_VERSION) {
    fprintf(stderr, "sear: this firmware's HAL runtime does not match the simulator; rebuild it\n");
    _exit(2);
  }
  sear_mcu.link = link;
  /* Named by the simulator rather than read from getppid(): if the simulator died before this
   * ran, the parent is already the reaper. */
  const char *sim_pid = getenv(SEAR_SIM_PID_ENV);
  simulator = sim_pid ? (pid_t)atol(sim_pid) : getppid();
  atexit(at_exit);
}
