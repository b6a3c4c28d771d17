/* The firmware side's end of the lockstep link (see firmware_end.h). */
#define _GNU_SOURCE
#include "firmware_end.h"

#include <stdio.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <unistd.h>

#include "lockstep_handoff.h"

/* Spinning this long covers a physics step with room to spare; beyond it the simulator is
 * probably busy with other MCUs, and sleeping frees the core for them. */
#define SPIN_NS 200000

static pid_t simulator;

struct sear_link *sear_end_attach(const char *who, const char *outside_sear, const char *mismatch) {
  const char *fd_text = getenv(SEAR_LINK_FD_ENV);
  if (!fd_text) {
    fprintf(stderr, "%s\n", outside_sear);
    _exit(2);
  }
  const int fd = atoi(fd_text);
  void *page = mmap(NULL, sizeof(struct sear_link), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  if (page == MAP_FAILED) {
    fprintf(stderr, "%s: ", who);
    perror("mapping the lockstep link");
    _exit(2);
  }
  close(fd);
  struct sear_link *link = page;
  if (link->magic != SEAR_LINK_MAGIC || link->version != SEAR_LINK_VERSION) {
    fprintf(stderr, "%s\n", mismatch);
    _exit(2);
  }
  /* Named by the simulator rather than read from getppid(): if the simulator died before this
   * ran, the parent is already the reaper. */
  const char *sim_pid = getenv(SEAR_SIM_PID_ENV);
  simulator = sim_pid ? (pid_t)atol(sim_pid) : getppid();
  return link;
}

/* The parent-death signal the simulator sets up kills the process at once; this look, once a
 * second, is for the moment before that signal was armed. */
void sear_end_wait_for_turn(struct sear_link *link) {
  while (!sear_handoff_wait(&link->turn, SEAR_TURN_FIRMWARE, &link->firmware_waiting, SPIN_NS, 1000000000))
    if (getppid() != simulator) _exit(3);
}

void sear_end_give(struct sear_link *link, enum sear_request request) {
  link->request = (uint32_t)request;
  sear_handoff_give(&link->turn, SEAR_TURN_SIM, &link->sim_waiting);
}

void sear_end_push_event(struct sear_link *link, enum sear_event_kind kind, uint8_t index, uint32_t value,
                         int64_t time_ns) {
  struct sear_event *e = &link->events[link->event_count];
  e->time_ns = time_ns;
  e->value = value;
  e->kind = (uint8_t)kind;
  e->index = index;
  __atomic_store_n(&link->event_count, link->event_count + 1, __ATOMIC_RELEASE);
}

void sear_end_set_fatal(struct sear_link *link, const char *format, va_list args) {
  vsnprintf(link->fatal, sizeof link->fatal, format, args);
}
