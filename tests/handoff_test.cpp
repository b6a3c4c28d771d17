// The hand-off of the lockstep turn: a process that may run on one CPU only yields at once, since
// spinning would only keep the peer it waits for off that CPU; given two, it spins briefly first.
#include <gtest/gtest.h>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include "lockstep_handoff.h"

namespace {

// sear_handoff_spin_pauses() in a child confined to the first `cpus` CPUs this process may use.
// The answer is kept per process and a child inherits it: this test's process never asks itself.
unsigned pauses_with(int cpus) {
  int fds[2];
  if (pipe(fds) != 0) return 9999;
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    return 9999;
  }
  if (pid == 0) {
    cpu_set_t allowed, kept;
    CPU_ZERO(&kept);
    if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) _exit(1);
    for (int cpu = 0, n = 0; cpu < CPU_SETSIZE && n < cpus; ++cpu)
      if (CPU_ISSET(cpu, &allowed)) {
        CPU_SET(cpu, &kept);
        ++n;
      }
    unsigned pauses = 9999;
    if (sched_setaffinity(0, sizeof kept, &kept) == 0) pauses = sear_handoff_spin_pauses();
    const ssize_t written = write(fds[1], &pauses, sizeof pauses);
    _exit(written == sizeof pauses ? 0 : 1);
  }
  close(fds[1]);
  unsigned pauses = 9999;
  if (read(fds[0], &pauses, sizeof pauses) != sizeof pauses) pauses = 9999;
  close(fds[0]);
  waitpid(pid, nullptr, 0);
  return pauses;
}

TEST(Handoff, SpinsOnlyWhereThePeerCanRunBesideIt) {
  EXPECT_EQ(pauses_with(1), 0u);
  cpu_set_t allowed;
  ASSERT_EQ(sched_getaffinity(0, sizeof allowed, &allowed), 0);
  if (CPU_COUNT(&allowed) < 2) GTEST_SKIP() << "one CPU here: nothing to compare with";
  const unsigned two = pauses_with(2);
  EXPECT_GT(two, 0u);
  EXPECT_LT(two, 1000u);  // a few dozen: past that, a peer sharing a core starves (see the source)
}

}  // namespace
