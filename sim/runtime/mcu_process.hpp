// One MCU's firmware running as its own process, and the simulator's end of the lockstep link
// with it: starting it, handing it each quantum, checking what it hands back, and noticing when it
// exits, crashes, hangs or overwrites the link.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "link_check.h"
#include "lockstep_link.h"

namespace sear {

// Why a firmware stopped taking part in the run.
struct McuFailure {
  enum class Kind { Exited, Crashed, Hung, Refused, Corrupted } kind;
  int code = 0;           // exit code, or the signal number
  std::string detail;     // the signal's name, the HAL's reason, or the link field found wrong
  std::int64_t time_ns;   // the firmware's clock at its last checked hand-back
  std::string last_call;  // the name of its last HAL call
};

// The MCU halted for good in an endless empty loop (`while (true);`) but stays in the run: its
// interrupts still run (unless they were off), its queued bytes still leave.
struct McuHalt {
  std::int64_t time_ns;  // when it entered the loop
  bool interrupts_off;   // halted with interrupts off (or inside a handler): nothing more runs
};

// "an endless empty loop; its interrupts still run" or "...; interrupts off, nothing more runs"
std::string describe(const McuHalt& halt);

// "exited with code 0", "crashed with signal 11 (SIGSEGV)", ...
std::string describe(const McuFailure& failure);
// "exited", "crashed", "hung", "refused", "corrupted": the summary's kind.
const char* kind_name(McuFailure::Kind kind);

const char* hal_call_name(std::uint32_t call);

struct McuProcessOptions {
  double hang_timeout_s = 5;
  std::int64_t call_cost_ns = 0;               // what one HAL call costs, the simulator's own copy
  std::uint64_t max_file_bytes = UINT64_MAX;   // the most the firmware may write to any one file
  std::vector<std::string> args;               // after its name: an engine's own arguments (engines/avr)
  std::string eeprom_file;                     // kept EEPROM (SEAR_EEPROM_FD_ENV), created if missing; empty: none
  std::vector<std::string> pass_env;           // the simulator's variables it gets too, if set (an engine's own)
};

class McuProcess {
 public:
  // Starts `executable` with the link already set up by `setup`, which fills in the wiring.
  // Its standard output and error go to `host_log`. Throws std::runtime_error if it cannot start.
  McuProcess(const std::string& executable, const std::string& host_log, const McuProcessOptions& options,
             void (*setup)(sear_link&, const void*), const void* setup_context);
  ~McuProcess();
  McuProcess(const McuProcess&) = delete;
  McuProcess& operator=(const McuProcess&) = delete;

  // Only for what the simulator writes: samples and received bytes for the coming quantum.
  sear_link& link() { return *link_; }

  // Hands the firmware the quantum that ends at end_ns (samples and bytes already in the link).
  void start_quantum(std::int64_t end_ns);
  // Lends the turn back without a new quantum, after its full event queue was emptied.
  void resume();

  enum class Turn { QuantumDone, Drain, Stopped, Interrupted };
  // Waits for the firmware to hand the turn back, and checks what it says. Stopped: see
  // failure(). Interrupted: the run was asked to stop (Ctrl-C, SIGTERM, SIGHUP) meanwhile.
  Turn wait();
  // The events of the turn just handed back, each checked; on a bad one the MCU is stopped as
  // corrupted and only the good ones before it are returned.
  const std::vector<sear_event>& events();
  const std::optional<McuFailure>& failure() const { return failure_; }
  // The firmware's clock at its last checked hand-back.
  std::int64_t clock_ns() const { return watch_.clock_ns; }
  // Set from the turn at which the firmware reported that it halted.
  const std::optional<McuHalt>& halt() const { return halt_; }
  // Whether the firmware has written to its standard output (not its stderr) so far.
  bool wrote_stdout();
  // Its last HAL call as last checked, not as the firmware may since have written it.
  const char* last_call_name() const { return hal_call_name(watch_.last_call); }

 private:
  void spawn(const std::string& executable, const std::string& host_log, const McuProcessOptions& options);
  void stop(McuFailure failure);
  void corrupted(const char* why);
  void read_unfinished_turn();
  void kill_group();
  Turn await_exit();
  McuFailure failure_from_status(int status) const;
  McuFailure failure_now(McuFailure::Kind kind) const;

  sear_link* link_ = nullptr;
  int fd_ = -1;
  int stdout_fd_ = -1;  // the same open file as the firmware's stdout: its offset tells it printed
  bool stdout_seen_ = false;
  pid_t pid_ = -1;  // also its process group
  double hang_timeout_s_;
  sear_link_watch watch_;
  sear_link_turn turn_{};
  // When the turn went to the firmware, and how long to spin for it next time (see wait()).
  std::chrono::steady_clock::time_point given_at_{};
  std::int64_t spin_ns_;
  std::int64_t turn_floor_ns_;
  std::vector<sear_event> events_;
  std::optional<McuFailure> failure_;
  std::optional<McuHalt> halt_;
};

}  // namespace sear
