#include "runtime/mcu_process.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/personality.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <new>
#include <stdexcept>

#include "lockstep_handoff.h"
#include "runtime/process_keeper.hpp"
#include "runtime/stop_request.hpp"
#include "runtime/while_waiting.hpp"

namespace sear {
namespace {

// Spin while the firmware runs a short quantum; sleep when it takes longer, so that the other
// MCUs and the firmware itself get the cores. A firmware whose turns take longer than the shortest
// spin (the AVR engine's quantum of 16 000 instructions is about 300 us) is waited for by spinning
// up to twice what its turns take: sleeping cost each of its turns the futex wake-up (tens of us
// on these machines, 10-25 % of the avoider's speed on the AVR engine). The spin yields, so a peer
// that needs this core still gets it.
constexpr std::int64_t kSpinNs = 200'000;
constexpr std::int64_t kSpinMaxNs = 2'000'000;
// How often a waiting simulator looks whether the firmware died or hung, or the run was asked to
// stop, meanwhile: well within the second a Ctrl-C may take.
constexpr std::int64_t kCheckNs = 10'000'000;

// Fixed descriptor numbers in the firmware: the link, and the executable it was started from,
// so that the path the kernel records for it ("/dev/fd/4") is the same in every run.
constexpr int kLinkFd = 3;
constexpr int kExecutableFd = 4;
constexpr int kExecReportFd = 5;  // closed by a successful exec
constexpr int kEepromFd = 6;      // the kept EEPROM's file, when the project keeps it

#define SEAR_CALL_NAME(name) #name,
const char* const kCallNames[] = {SEAR_HAL_CALLS(SEAR_CALL_NAME)};
#undef SEAR_CALL_NAME

// A firmware sees the same environment in every run, whatever the user's shell holds, so that
// its stack (where the kernel copies the environment) sits at the same addresses. Only the
// sanitizers' own settings pass, for sanitizer builds of the tests, and to an engine those it
// asks for (McuProcessOptions::pass_env), which are no firmware's. Every symbol is bound at
// load, before the stack is painted (startup_memory.c): bound lazily, a function's first call
// runs the dynamic linker's resolver, which saves the vector registers (XSAVEC) a few hundred
// bytes below the caller, and whether the SSE state reads as in use there depends on the host's
// context switches, so those bytes differed between runs where uninitialised stack is read next.
std::vector<std::string> firmware_environment(bool eeprom, const std::vector<std::string>& pass_env) {
  std::vector<std::string> env{fmt::format("{}={}", SEAR_LINK_FD_ENV, kLinkFd), "LD_BIND_NOW=1",
                               fmt::format("{}={:010d}", SEAR_SIM_PID_ENV, getpid())};
  if (eeprom) env.push_back(fmt::format("{}={}", SEAR_EEPROM_FD_ENV, kEepromFd));
  const auto pass = [&env](const std::string& name) {
    if (const char* value = std::getenv(name.c_str())) env.push_back(fmt::format("{}={}", name, value));
  };
  for (const char* name : {"ASAN_OPTIONS", "UBSAN_OPTIONS", "LSAN_OPTIONS"}) pass(name);
  for (const std::string& name : pass_env) pass(name);
  return env;
}

// Moves a descriptor above the ones the child is about to set up.
int out_of_the_way(int fd) { return fcntl(fd, F_DUPFD_CLOEXEC, 100); }

}  // namespace

const char* hal_call_name(std::uint32_t call) {
  return call < SEAR_CALL_COUNT ? kCallNames[call] : "unknown";
}

const char* kind_name(McuFailure::Kind kind) {
  switch (kind) {
    case McuFailure::Kind::Exited: return "exited";
    case McuFailure::Kind::Crashed: return "crashed";
    case McuFailure::Kind::Hung: return "hung";
    case McuFailure::Kind::Refused: return "refused";
    case McuFailure::Kind::Corrupted: return "corrupted";
  }
  return "stopped";
}

std::string describe(const McuFailure& f) {
  switch (f.kind) {
    case McuFailure::Kind::Exited: return fmt::format("exited with code {}", f.code);
    case McuFailure::Kind::Crashed: return fmt::format("crashed with signal {} ({})", f.code, f.detail);
    case McuFailure::Kind::Hung: return fmt::format("hung: {}", f.detail);
    case McuFailure::Kind::Refused: return fmt::format("stopped by the HAL: {}", f.detail);
    case McuFailure::Kind::Corrupted: return fmt::format("overwrote the simulator link at {}; stopped", f.detail);
  }
  return "stopped";
}

std::string describe(const McuHalt& h) {
  return h.interrupts_off ? "an endless empty loop with interrupts off; nothing more runs on it"
                          : "an endless empty loop; its interrupts still run";
}

McuProcess::McuProcess(const std::string& executable, const std::string& host_log, const McuProcessOptions& options,
                       void (*setup)(sear_link&, const void*), const void* setup_context)
    : hang_timeout_s_(options.hang_timeout_s), spin_ns_(kSpinNs), turn_floor_ns_(kSpinNs / 2) {
  sear_link_watch_init(&watch_, options.call_cost_ns);
  fd_ = memfd_create("sear-link", MFD_CLOEXEC);
  if (fd_ < 0 || ftruncate(fd_, sizeof(sear_link)) != 0)
    throw std::runtime_error(fmt::format("cannot create the lockstep link: {}", std::strerror(errno)));
  void* page = mmap(nullptr, sizeof(sear_link), PROT_READ | PROT_WRITE, MAP_SHARED, fd_, 0);
  if (page == MAP_FAILED) throw std::runtime_error(fmt::format("cannot map the lockstep link: {}", std::strerror(errno)));
  link_ = new (page) sear_link{};
  link_->magic = SEAR_LINK_MAGIC;
  link_->version = SEAR_LINK_VERSION;
  link_->guard_front = SEAR_LINK_GUARD;
  link_->guard_back = SEAR_LINK_GUARD;
  link_->turn = SEAR_TURN_SIM;
  setup(*link_, setup_context);
  spawn(executable, host_log, options);
}

void McuProcess::spawn(const std::string& executable, const std::string& host_log, const McuProcessOptions& options) {
  const std::uint64_t max_file_bytes = options.max_file_bytes;
  const std::vector<std::string>& args = options.args;
  const bool eeprom = !options.eeprom_file.empty();
  const int kept = eeprom ? open(options.eeprom_file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644) : -1;
  if (eeprom && kept < 0)
    throw std::runtime_error(fmt::format("{}: error: cannot open the kept EEPROM's file: {}", options.eeprom_file,
                                         std::strerror(errno)));
  const int exe = open(executable.c_str(), O_RDONLY | O_CLOEXEC);
  if (exe < 0) {
    const int error = errno;
    if (kept >= 0) close(kept);
    throw std::runtime_error(fmt::format("cannot start firmware {}: {}", executable, std::strerror(error)));
  }
  // Its stdout and stderr go to the one log, each through its own open file, both appending: the
  // offset of the stdout's (which this process keeps) then moves only when the firmware prints.
  const int log = open(host_log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644);
  const int out = log < 0 ? -1 : open(host_log.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (out < 0) {
    const int error = errno;
    close(exe);
    if (kept >= 0) close(kept);
    if (log >= 0) close(log);
    throw std::runtime_error(fmt::format("{}: error: cannot write: {}", host_log, std::strerror(error)));
  }
  stdout_fd_ = out;
  // Everything the child needs is prepared here: after fork() it may only make system calls.
  const std::vector<std::string> env_text = firmware_environment(eeprom, options.pass_env);
  std::vector<char*> env;
  for (const auto& e : env_text) env.push_back(const_cast<char*>(e.c_str()));
  env.push_back(nullptr);
  char name[] = "firmware";
  std::vector<char*> argv{name};
  for (const auto& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  char empty[] = "";
  const char* const path = executable.c_str();
  const pid_t simulator = getpid();
  const int link_fd = out_of_the_way(fd_), exe_fd = out_of_the_way(exe), log_fd = out_of_the_way(log),
            out_fd = out_of_the_way(out), eeprom_fd = kept >= 0 ? out_of_the_way(kept) : -1;
  close(exe);
  close(log);
  if (kept >= 0) close(kept);
  const rlim_t limit = max_file_bytes >= RLIM_INFINITY ? RLIM_INFINITY : static_cast<rlim_t>(max_file_bytes);
  // The child reports a failed exec through this pipe; a successful one closes it unwritten.
  int exec_report[2];
  if (pipe2(exec_report, O_CLOEXEC) != 0) exec_report[0] = exec_report[1] = -1;
  const int report_fd = exec_report[1] >= 0 ? out_of_the_way(exec_report[1]) : -1;
  if (exec_report[1] >= 0) close(exec_report[1]);

  pid_ = fork();
  if (pid_ == 0) {
    // Its own process group, which the simulator kills as a whole, forked children included;
    // and Ctrl-C at the terminal reaches the simulator only, which then stops the firmware
    // rather than finding it killed and reporting a crash.
    setpgid(0, 0);
    // Dies with the simulator, whatever kills it; if the simulator is already gone, at once.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != simulator) _exit(127);
    // A real MCU has fixed addresses: no address-space randomisation, so a firmware that prints
    // a pointer or reads uninitialised memory does the same in every run.
    const int persona = personality(0xffffffff);
    if (persona != -1) personality(static_cast<unsigned long>(persona) | ADDR_NO_RANDOMIZE);
    // No file it writes, its host log included, grows past the limit: the write fails instead.
    const struct rlimit file_size = {limit, limit};
    setrlimit(RLIMIT_FSIZE, &file_size);
    for (const int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) signal(s, SIG_DFL);
    signal(SIGXFSZ, SIG_IGN);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    const int null = open("/dev/null", O_RDONLY);
    dup2(null, STDIN_FILENO);
    dup2(out_fd, STDOUT_FILENO);
    dup2(log_fd, STDERR_FILENO);
    dup2(link_fd, kLinkFd);                    // without close-on-exec: the firmware maps it
    dup3(exe_fd, kExecutableFd, O_CLOEXEC);
    if (report_fd >= 0) dup3(report_fd, kExecReportFd, O_CLOEXEC);
    if (eeprom_fd >= 0) dup2(eeprom_fd, kEepromFd);  // without close-on-exec: the firmware keeps it
    syscall(SYS_close_range, static_cast<unsigned>(eeprom_fd >= 0 ? kEepromFd + 1 : kEepromFd), ~0u, 0u);
    syscall(SYS_execveat, kExecutableFd, empty, argv.data(), env.data(), AT_EMPTY_PATH);
    // A script (#!) cannot be run from a descriptor closed on exec, as its interpreter opens the
    // path "/dev/fd/4": it runs from its own path, which only its addresses depend on.
    if (errno == ENOENT) execve(path, argv.data(), env.data());
    const int exec_error = errno;
    const ssize_t reported = write(kExecReportFd, &exec_error, sizeof exec_error);
    _exit(reported == static_cast<ssize_t>(sizeof exec_error) ? 127 : 126);
  }
  const int fork_error = errno;
  close(link_fd);
  close(exe_fd);
  close(log_fd);
  close(out_fd);
  if (eeprom_fd >= 0) close(eeprom_fd);
  if (report_fd >= 0) close(report_fd);
  if (pid_ < 0) {
    pid_ = -1;
    if (exec_report[0] >= 0) close(exec_report[0]);
    throw std::runtime_error(fmt::format("cannot start firmware {}: {}", executable, std::strerror(fork_error)));
  }
  int exec_error = 0;
  ssize_t got = -1;
  while (exec_report[0] >= 0 && (got = read(exec_report[0], &exec_error, sizeof exec_error)) < 0 && errno == EINTR) {
  }
  if (exec_report[0] >= 0) close(exec_report[0]);
  if (got == static_cast<ssize_t>(sizeof exec_error)) {
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
    throw std::runtime_error(fmt::format("cannot start firmware {}: {}", executable, std::strerror(exec_error)));
  }
  setpgid(pid_, pid_);  // also here, so that the group exists before anything signals it
  keeper_watch(pid_);
}

McuProcess::~McuProcess() {
  kill_group();
  if (link_) munmap(link_, sizeof(sear_link));
  if (fd_ >= 0) close(fd_);
  if (stdout_fd_ >= 0) close(stdout_fd_);
}

bool McuProcess::wrote_stdout() {
  if (!stdout_seen_ && stdout_fd_ >= 0) stdout_seen_ = lseek(stdout_fd_, 0, SEEK_CUR) > 0;
  return stdout_seen_;
}

// The firmware and whatever it forked, stopped ones included: SIGKILL needs no cooperation.
void McuProcess::kill_group() {
  if (pid_ <= 0) return;
  kill(-pid_, SIGKILL);
  while (waitpid(pid_, nullptr, 0) < 0 && errno == EINTR) {
  }
  keeper_forget(pid_);
  pid_ = -1;
}

void McuProcess::start_quantum(std::int64_t end_ns) {
  link_->quantum_end_ns = end_ns;
  link_->event_count = 0;
  watch_.quantum_end_ns = end_ns;
  watch_.turn_clock_ns = watch_.clock_ns;
  given_at_ = std::chrono::steady_clock::now();
  sear_handoff_give(&link_->turn, SEAR_TURN_FIRMWARE, &link_->firmware_waiting);
}

void McuProcess::resume() {
  link_->event_count = 0;
  // The HAL charged the call whose event found the queue full before handing over: that event,
  // and any other of the same call, is stamped one call's cost before the clock it reported.
  watch_.turn_clock_ns = std::max(watch_.turn_clock_ns, watch_.clock_ns - watch_.call_cost_ns);
  given_at_ = std::chrono::steady_clock::now();
  sear_handoff_give(&link_->turn, SEAR_TURN_FIRMWARE, &link_->firmware_waiting);
}

McuFailure McuProcess::failure_now(McuFailure::Kind kind) const {
  return McuFailure{kind, 0, "", watch_.clock_ns, hal_call_name(watch_.last_call)};
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
  kill_group();
}

void McuProcess::corrupted(const char* why) {
  McuFailure f = failure_now(McuFailure::Kind::Corrupted);
  f.detail = why;
  turn_.event_count = 0;
  stop(f);
}

// A firmware that died or hung during its turn never handed it back: its clock, last call and
// the events it published are still read, if they check out, so that the report says where it
// was and nothing it did before is lost.
void McuProcess::read_unfinished_turn() {
  char why[256];
  if (sear_link_check_turn(link_, 0, &watch_, &turn_, why, sizeof why) != 0) turn_.event_count = 0;
}

const std::vector<sear_event>& McuProcess::events() {
  events_.clear();
  for (std::uint32_t i = 0; i < turn_.event_count; ++i) {
    sear_event e;
    char why[256];
    if (sear_link_check_event(link_, i, &watch_, &e, why, sizeof why) != 0) {
      corrupted(why);
      break;
    }
    events_.push_back(e);
  }
  turn_.event_count = 0;
  return events_;
}

// Its destructors and atexit handlers still run; they get the hang timeout to finish.
McuProcess::Turn McuProcess::await_exit() {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(hang_timeout_s_);
  for (;;) {
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      stop(failure_from_status(status));  // anything it forked goes with it
      return Turn::Stopped;
    }
    if (stop_requested()) return Turn::Interrupted;
    while_waiting();
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
  std::int64_t clock = watch_.clock_ns;
  auto progress_at = Clock::now();
  // Only a clock that moves forward within its quantum is progress: a firmware that scribbles its
  // clock (or a thread of it that keeps bumping it) must not hold off the hang check for ever.
  const std::int64_t latest = watch_.quantum_end_ns + watch_.call_cost_ns;
  for (;;) {
    if (sear_handoff_wait(&link_->turn, SEAR_TURN_SIM, &link_->sim_waiting, spin_ns_, kCheckNs)) {
      const std::int64_t took = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - given_at_).count();
      // The turns' recent floor, which grows by half a step at most: one long turn (the firmware
      // waited for a core) leaves it, and so the spin, where it was; turns that are all long raise
      // it within a few. Spinning on for a firmware that waits for a core only keeps the core busy.
      turn_floor_ns_ = std::min(took, turn_floor_ns_ + turn_floor_ns_ / 2);
      spin_ns_ = std::clamp(2 * turn_floor_ns_, kSpinNs, kSpinMaxNs);
      char why[256];
      if (sear_link_check_turn(link_, 1, &watch_, &turn_, why, sizeof why) != 0) {
        corrupted(why);
        return Turn::Stopped;
      }
      if (turn_.halt && !halt_) halt_ = McuHalt{turn_.halted_ns, turn_.halt == SEAR_HALT_EMPTY_LOOP_IRQ_OFF};
      switch (turn_.request) {
        case SEAR_REQUEST_QUANTUM_DONE: return Turn::QuantumDone;
        case SEAR_REQUEST_DRAIN:
          // A full queue with the clock where the turn began: pins or ports written in a loop
          // that takes no simulated time, which would otherwise fill the disk, not the quantum.
          if (turn_.clock_ns == watch_.turn_clock_ns) {
            McuFailure f = failure_now(McuFailure::Kind::Hung);
            f.detail = fmt::format(
                "it wrote {} pin or port events without its clock moving (a loop that takes no simulated time{}); "
                "stopped",
                turn_.event_count, watch_.call_cost_ns == 0 ? ", as HAL calls cost nothing with hal_call_cycles=\"0\"" : "");
            stop(f);  // its events up to here are still in the link, and still passed on
            return Turn::Stopped;
          }
          return Turn::Drain;
        case SEAR_REQUEST_FATAL: {
          McuFailure f = failure_now(McuFailure::Kind::Refused);
          f.detail = turn_.fatal;
          stop(f);
          return Turn::Stopped;
        }
        default:  // SEAR_REQUEST_EXIT: main() returned or exit() was called; its status follows
          return await_exit();
      }
    }
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      read_unfinished_turn();
      stop(failure_from_status(status));  // reaped already; this ends what it forked
      return Turn::Stopped;
    }
    if (stop_requested()) return Turn::Interrupted;
    while_waiting();  // every kCheckNs while the firmware keeps its turn
    // Hung: its clock stood still for the whole timeout, because it made no HAL call (or only
    // calls that cost nothing, with hal_call_cycles="0"). The raw value only tells progress.
    const std::int64_t now_clock = __atomic_load_n(&link_->clock_ns, __ATOMIC_RELAXED);
    if (now_clock > clock && now_clock <= latest) {
      clock = now_clock;
      progress_at = Clock::now();
    } else if (std::chrono::duration<double>(Clock::now() - progress_at).count() >= hang_timeout_s_) {
      read_unfinished_turn();
      McuFailure f = failure_now(McuFailure::Kind::Hung);
      f.detail = fmt::format("its clock stood still for {:g} s of host time (no HAL call); stopped", hang_timeout_s_);
      stop(f);
      return Turn::Stopped;
    }
  }
}

}  // namespace sear
