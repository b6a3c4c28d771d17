// One MCU's firmware running as its own process, and the simulator's end of the lockstep link
// with it: starting it, handing it each quantum, and noticing when it exits, crashes or hangs.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <string>

#include "runtime/lockstep_link.h"

namespace sear {

// Why a firmware stopped taking part in the run.
struct McuFailure {
  enum class Kind { Exited, Crashed, Hung, Refused } kind;
  int code = 0;           // exit code, or the signal number
  std::string detail;     // the signal's name, or the HAL's reason for refusing a call
  std::int64_t time_ns;   // the firmware's own clock at its last HAL call
  std::string last_call;  // the name of that call
};

// "exited with code 0", "crashed with signal 11 (SIGSEGV)", ...
std::string describe(const McuFailure& failure);

const char* hal_call_name(std::uint32_t call);

class McuProcess {
 public:
  // Starts `executable` with the link already set up by `setup`, which fills in the wiring.
  // Its standard output and error go to `host_log`. Throws std::runtime_error if it cannot start.
  McuProcess(const std::string& executable, const std::string& host_log, double hang_timeout_s,
             void (*setup)(sear_link&, const void*), const void* setup_context);
  ~McuProcess();
  McuProcess(const McuProcess&) = delete;
  McuProcess& operator=(const McuProcess&) = delete;

  sear_link& link() { return *link_; }

  // Hands the firmware the quantum that ends at end_ns (samples and bytes already in the link).
  void start_quantum(std::int64_t end_ns);
  // Lends the turn back without a new quantum, after its full event queue was emptied.
  void resume();

  enum class Turn { QuantumDone, Drain, Stopped };
  // Waits for the firmware to hand the turn back. Stopped: see failure().
  Turn wait();
  const std::optional<McuFailure>& failure() const { return failure_; }

 private:
  void stop(McuFailure failure);
  Turn await_exit();
  McuFailure failure_from_status(int status) const;
  McuFailure failure_now(McuFailure::Kind kind) const;

  sear_link* link_ = nullptr;
  int fd_ = -1;
  pid_t pid_ = -1;
  double hang_timeout_s_;
  std::optional<McuFailure> failure_;
};

}  // namespace sear
