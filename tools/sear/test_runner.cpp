#include "sear/test_runner.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <map>

#include "runtime/stop_request.hpp"

extern char** environ;

namespace sear {
namespace {

// posix_spawn rather than fork: no copy of this process's memory per run, and the working folder
// and the log are set up by the C library between fork and exec.
pid_t spawn(const ChildRun& child) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, child.cwd.c_str());
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, child.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  std::vector<char*> argv;
  for (const std::string& a : child.argv) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return error == 0 ? pid : -1;
}

int exit_code(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 1;
}

}  // namespace

bool run_children(const std::vector<ChildRun>& children, std::size_t jobs,
                  const std::function<void(std::size_t, int)>& done) {
  std::map<pid_t, std::size_t> running;
  std::size_t next = 0;
  bool passed_on = false;
  while (next < children.size() || !running.empty()) {
    if (stop_requested() && !passed_on) {
      // A terminal's Ctrl-C reaches the children too; a SIGTERM sent to us alone does not.
      for (const auto& [pid, index] : running) kill(pid, stop_signal());
      passed_on = true;
    }
    while (!stop_requested() && next < children.size() && running.size() < std::max<std::size_t>(jobs, 1)) {
      const pid_t pid = spawn(children[next]);
      if (pid < 0) done(next, 127);
      else running.emplace(pid, next);
      ++next;
    }
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;  // a stop request: pass it on above
      break;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const std::size_t index = it->second;
    running.erase(it);
    done(index, exit_code(status));
  }
  return next == children.size();
}

}  // namespace sear
