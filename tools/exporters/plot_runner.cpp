#include "exporters/plot_runner.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <string.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <vector>

#include "runtime/stop_request.hpp"

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

std::string script_path() { return env_or("SEAR_PLOT_SCRIPT", SEAR_PLOT_SCRIPT); }

// Starts `PYTHON SCRIPT out_dir` with its output in out_dir/plots.log and no other file of the run
// open; `keep_fd` (or -1) is handed on as its fd 3, `detach` puts it in a session of its own, so
// that it outlives the run without a terminal's signals. 0 (after a warning) if it did not start.
pid_t spawn_plotter(const std::string& out_dir, int keep_fd, bool detach) {
  const std::string python = env_or("SEAR_PYTHON", "/usr/bin/python3");
  const std::string script = script_path();
  const std::string log = out_dir + "/plots.log";

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  if (keep_fd >= 0) posix_spawn_file_actions_adddup2(&actions, keep_fd, 3);
  posix_spawn_file_actions_addclosefrom_np(&actions, keep_fd >= 0 ? 4 : 3);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  if (detach) posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSID);
  std::vector<char*> argv{const_cast<char*>(python.c_str()), const_cast<char*>(script.c_str()),
                          const_cast<char*>(out_dir.c_str()), nullptr};
  pid_t pid = 0;
  const int error = posix_spawn(&pid, python.c_str(), &actions, &attributes, argv.data(), environ);
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) {
    warn(fmt::format("cannot start {} ({}); install python3-matplotlib, or name an interpreter in SEAR_PYTHON",
                     python, strerror(error)));
    return 0;
  }
  return pid;
}

}  // namespace

bool write_plots(const std::string& out_dir) {
  const std::string script = script_path();
  const std::string log = out_dir + "/plots.log";
  const pid_t pid = spawn_plotter(out_dir, -1, false);
  if (pid == 0) return false;
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

namespace sear {

PlotFolder::~PlotFolder() {
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

void PlotFolder::claim(bool quiet) {
  if (lock_fd_ < 0) {
    const int fd = ::open(out_dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;  // the run's own writes report an unusable folder
    // Above the descriptors a plotter is handed (0 to 3), so that spawning it never clobbers this.
    lock_fd_ = fcntl(fd, F_DUPFD_CLOEXEC, 10);
    ::close(fd);
    if (lock_fd_ < 0) return;
  }
  if (flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    if (!quiet) fmt::print(stderr, "sear: waiting for the plots of the previous run in {} to be drawn\n", out_dir_);
    while (flock(lock_fd_, LOCK_EX) != 0)
      if (errno != EINTR || stop_requested()) return;  // the run stops at once, before its first step
  }
  std::error_code ignored;
  for (const auto& entry : std::filesystem::directory_iterator(out_dir_, ignored)) {
    const std::string name = entry.path().filename().string();
    const auto ends_with = [&](std::string_view end) {
      return name.size() >= end.size() && name.compare(name.size() - end.size(), end.size(), end) == 0;
    };
    if ((name.rfind("plot_", 0) == 0 && (ends_with(".png") || ends_with(".png.part"))) || name == "plots.log")
      std::filesystem::remove(entry.path(), ignored);
  }
}

void PlotFolder::wait_for_plotter(const std::string& out_dir) {
  const int fd = ::open(out_dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  while (flock(fd, LOCK_EX) != 0)
    if (errno != EINTR || stop_requested()) break;
  ::close(fd);  // lets go of the lock too
}

bool PlotFolder::draw_in_background() {
  if (lock_fd_ < 0) return spawn_plotter(out_dir_, -1, true) != 0;
  const bool started = spawn_plotter(out_dir_, lock_fd_, true) != 0;
  // The plotter holds the lock now, through its copy of the descriptor; this run lets go of it.
  ::close(lock_fd_);
  lock_fd_ = -1;
  return started;
}

}  // namespace sear
