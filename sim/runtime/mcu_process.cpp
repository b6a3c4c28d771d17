#include "runtime/mcu_process.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <new>
#include <stdexcept>
#include <vector>

#include "runtime/lockstep_handoff.h"

extern char** environ;

namespace sear {
namespace {

// Spin while the firmware runs a short quantum; sleep when it takes longer, so that the other
// MCUs and the firmware itself get the cores.
constexpr std::int64_t kSpinNs = 200'000;
// How often a sleeping simulator looks whether the firmware died or hung meanwhile.
constexpr std::int64_t kCheckNs = 10'000'000;

#define SEAR_CALL_NAME(name) #name,
const char* const kCallNames[] = {SEAR_HAL_CALLS(SEAR_CALL_NAME)};
#undef SEAR_CALL_NAME

}  // namespace

const char* hal_call_name(std::uint32_t call) {
  return call < SEAR_CALL_COUNT ? kCallNames[call] : "unknown";
}

std::string describe(const McuFailure& f) {
  switch (f.kind) {
    case McuFailure::Kind::Exited: return fmt::format("exited with code {}", f.code);
    case McuFailure::Kind::Crashed: return fmt::format("crashed with signal {} ({})", f.code, f.detail);
    case McuFailure::Kind::Hung: return fmt::format("hung: {}", f.detail);
    case McuFailure::Kind::Refused: return fmt::format("stopped by the HAL: {}", f.detail);
  }
  return "stopped";
}

McuProcess::McuProcess(const std::string& executable, const std::string& host_log, double hang_timeout_s,
                       void (*setup)(sear_link&, const void*), const void* setup_context)
    : hang_timeout_s_(hang_timeout_s) {
  fd_ = memfd_create("sear-link", 0);  // no MFD_CLOEXEC: the firmware inherits it
  if (fd_ < 0 || ftruncate(fd_, sizeof(sear_link)) != 0)
    throw std::runtime_error(fmt::format("cannot create the lockstep link: {}", std::strerror(errno)));
  void* page = mmap(nullptr, sizeof(sear_link), PROT_READ | PROT_WRITE, MAP_SHARED, fd_, 0);
  if (page == MAP_FAILED) throw std::runtime_error(fmt::format("cannot map the lockstep link: {}", std::strerror(errno)));
  link_ = new (page) sear_link{};
  link_->magic = SEAR_LINK_MAGIC;
  link_->version = SEAR_LINK_VERSION;
  link_->turn = SEAR_TURN_SIM;
  setup(*link_, setup_context);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, host_log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, STDIN_FILENO);
  // The link as descriptor 3, and nothing else of ours: not the run's output files, nor the
  // other MCUs' links, which a stray write could otherwise corrupt.
  constexpr int kLinkFd = 3;
  posix_spawn_file_actions_adddup2(&actions, fd_, kLinkFd);
  posix_spawn_file_actions_addclosefrom_np(&actions, kLinkFd + 1);
  std::vector<std::string> env_text;
  const auto ours = [](const char* entry, const char* name) {
    return std::strncmp(entry, name, std::strlen(name)) == 0 && entry[std::strlen(name)] == '=';
  };
  for (char** e = environ; *e; ++e)
    if (!ours(*e, SEAR_LINK_FD_ENV) && !ours(*e, SEAR_SIM_PID_ENV)) env_text.emplace_back(*e);
  env_text.push_back(fmt::format("{}={}", SEAR_LINK_FD_ENV, kLinkFd));
  env_text.push_back(fmt::format("{}={}", SEAR_SIM_PID_ENV, getpid()));
  std::vector<char*> env;
  for (auto& e : env_text) env.push_back(e.data());
  env.push_back(nullptr);
  std::string exe = executable;
  char* argv[] = {exe.data(), nullptr};
  // Its own process group: Ctrl-C at the terminal interrupts the run, which then stops the
  // firmware itself, rather than killing the firmware and reporting it as crashed.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  const int err = posix_spawn(&pid_, exe.c_str(), &actions, &attributes, argv, env.data());
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0) {
    pid_ = -1;
    throw std::runtime_error(fmt::format("cannot start firmware {}: {}", executable, std::strerror(err)));
  }
}

McuProcess::~McuProcess() {
  if (pid_ > 0) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
  if (link_) munmap(link_, sizeof(sear_link));
  if (fd_ >= 0) close(fd_);
}

void McuProcess::start_quantum(std::int64_t end_ns) {
  link_->quantum_end_ns = end_ns;
  link_->event_count = 0;
  sear_handoff_give(&link_->turn, SEAR_TURN_FIRMWARE, &link_->firmware_waiting);
}

void McuProcess::resume() {
  link_->event_count = 0;
  sear_handoff_give(&link_->turn, SEAR_TURN_FIRMWARE, &link_->firmware_waiting);
}

McuFailure McuProcess::failure_now(McuFailure::Kind kind) const {
  McuFailure f{kind, 0, "", link_->clock_ns, hal_call_name(link_->last_call)};
  return f;
}

McuFailure McuProcess::failure_from_status(int status) const {
  if (WIFSIGNALED(status)) {
    McuFailure f = failure_now(McuFailure::Kind::Crashed);
    f.code = WTERMSIG(status);
    const char* abbrev = sigabbrev_np(f.code);
    f.detail = fmt::format("SIG{}, {}", abbrev ? abbrev : "?", strsignal(f.code));
    return f;
  }
  McuFailure f = failure_now(McuFailure::Kind::Exited);
  f.code = WEXITSTATUS(status);
  return f;
}

void McuProcess::stop(McuFailure failure) {
  failure_ = std::move(failure);
  if (pid_ > 0) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }
}

// Its destructors and atexit handlers still run; they get the hang timeout to finish.
McuProcess::Turn McuProcess::await_exit() {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(hang_timeout_s_);
  for (;;) {
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      failure_ = failure_from_status(status);
      return Turn::Stopped;
    }
    if (Clock::now() > deadline) {
      McuFailure f = failure_now(McuFailure::Kind::Hung);
      f.detail = fmt::format("it called exit() but was still running {:g} s of host time later; stopped", hang_timeout_s_);
      stop(f);
      return Turn::Stopped;
    }
    usleep(1000);
  }
}

McuProcess::Turn McuProcess::wait() {
  if (failure_) return Turn::Stopped;
  using Clock = std::chrono::steady_clock;
  std::int64_t clock = link_->clock_ns;
  auto progress_at = Clock::now();
  for (;;) {
    if (sear_handoff_wait(&link_->turn, SEAR_TURN_SIM, &link_->sim_waiting, kSpinNs, kCheckNs)) {
      switch (link_->request) {
        case SEAR_REQUEST_QUANTUM_DONE: return Turn::QuantumDone;
        case SEAR_REQUEST_DRAIN: return Turn::Drain;
        case SEAR_REQUEST_FATAL: {
          McuFailure f = failure_now(McuFailure::Kind::Refused);
          f.detail.assign(link_->fatal, strnlen(link_->fatal, sizeof link_->fatal));
          stop(f);
          return Turn::Stopped;
        }
        case SEAR_REQUEST_EXIT:  // main() returned or exit() was called: its status follows
          return await_exit();
        default: {
          McuFailure f = failure_now(McuFailure::Kind::Refused);
          f.detail = fmt::format("it broke the lockstep protocol (request {}); did it write over the HAL's memory?",
                                 link_->request);
          stop(f);
          return Turn::Stopped;
        }
      }
    }
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      failure_ = failure_from_status(status);
      return Turn::Stopped;
    }
    // Hung: its clock stood still for the whole timeout, because it made no HAL call (or only
    // calls that cost nothing, with hal_call_cycles="0").
    const std::int64_t now_clock = __atomic_load_n(&link_->clock_ns, __ATOMIC_RELAXED);
    if (now_clock != clock) {
      clock = now_clock;
      progress_at = Clock::now();
    } else if (std::chrono::duration<double>(Clock::now() - progress_at).count() >= hang_timeout_s_) {
      McuFailure f = failure_now(McuFailure::Kind::Hung);
      f.detail = fmt::format("its clock stood still for {:g} s of host time (no HAL call); stopped", hang_timeout_s_);
      stop(f);
      return Turn::Stopped;
    }
  }
}

}  // namespace sear
