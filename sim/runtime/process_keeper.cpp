#include "runtime/process_keeper.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <initializer_list>

namespace sear {
namespace {

int g_pipe = -1;  // the write end; the keeper reads the other

// The keeper's whole life: a fixed table of groups, filled and emptied by messages until the pipe
// closes. Only system calls, since it runs in a child forked from the simulator.
[[noreturn]] void keeper_main(int from_simulator) {
  constexpr int kMaxGroups = 4096;
  static pid_t groups[kMaxGroups];
  int count = 0;
  for (;;) {
    std::int32_t message = 0;
    const ssize_t n = read(from_simulator, &message, sizeof message);
    if (n < 0 && errno == EINTR) continue;
    if (n != static_cast<ssize_t>(sizeof message)) break;  // closed: the simulator is gone
    if (message > 0 && count < kMaxGroups) {
      groups[count++] = message;
    } else if (message < 0) {
      for (int i = 0; i < count; ++i)
        if (groups[i] == -message) groups[i] = groups[--count];
    }
  }
  for (int i = 0; i < count; ++i) kill(-groups[i], SIGKILL);
  _exit(0);
}

}  // namespace

void keeper_start() {
  if (g_pipe >= 0) return;
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) return;  // no keeper: the parent-death signal still applies
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    return;
  }
  if (pid == 0) {
    // Its own process group, so that a Ctrl-C or a kill of the simulator's group does not end it
    // before it has done its job; it ends by itself once the simulator is gone.
    setpgid(0, 0);
    for (const int s : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGTSTP, SIGPIPE}) signal(s, SIG_IGN);
    dup2(fds[0], 0);
    syscall(SYS_close_range, 1u, ~0u, 0u);  // no output files, links or pipes of the run
    keeper_main(0);
  }
  close(fds[0]);
  g_pipe = fds[1];
}

namespace {

void send(std::int32_t message) {
  keeper_start();
  if (g_pipe < 0) return;
  while (write(g_pipe, &message, sizeof message) < 0 && errno == EINTR) {
  }
}

}  // namespace

void keeper_watch(pid_t process_group) { send(static_cast<std::int32_t>(process_group)); }

void keeper_forget(pid_t process_group) { send(-static_cast<std::int32_t>(process_group)); }

}  // namespace sear
