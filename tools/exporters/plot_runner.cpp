#include "exporters/plot_runner.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

extern char** environ;

namespace sear {
namespace {

std::string env_or(const char* name, const char* fallback) {
  const char* v = std::getenv(name);
  return v && *v ? v : fallback;
}

// The plotter's last line, which says why it gave up (it ends with one such line).
std::string last_line(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

void warn(const std::string& why) { fmt::print(stderr, "sear: warning: no plots: {}\n", why); }

}  // namespace

bool write_plots(const std::string& out_dir) {
  const std::string python = env_or("SEAR_PYTHON", "/usr/bin/python3");
  const std::string script = env_or("SEAR_PLOT_SCRIPT", SEAR_PLOT_SCRIPT);
  const std::string log = out_dir + "/plots.log";

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  std::vector<char*> argv{const_cast<char*>(python.c_str()), const_cast<char*>(script.c_str()),
                          const_cast<char*>(out_dir.c_str()), nullptr};
  pid_t pid = 0;
  const int error = posix_spawn(&pid, python.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) {
    warn(fmt::format("cannot start {} ({}); install python3-matplotlib, or name an interpreter in SEAR_PYTHON",
                     python, strerror(error)));
    return false;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) {
      warn(fmt::format("lost the plotter ({})", strerror(errno)));
      return false;
    }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    std::error_code ignored;  // an empty log says nothing: only a failed plotting leaves one
    if (std::filesystem::file_size(log, ignored) == 0) std::filesystem::remove(log, ignored);
    return true;
  }
  const std::string why = last_line(log);
  if (WIFSIGNALED(status))
    warn(fmt::format("{} was ended by signal {}", script, WTERMSIG(status)));
  else
    warn(fmt::format("{} failed{} (see {})", script, why.empty() ? "" : ": " + why, log));
  return false;
}

}  // namespace sear
