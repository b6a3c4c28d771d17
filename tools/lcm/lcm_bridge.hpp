// A run seen and steered over LCM: publishes the robots' poses, their sensors' readings, the bytes
// on their UARTs, CAN frames, the MCUs' outputs and the clock (and writes them into an LCM event
// log); takes drive commands for robots without an MCU and pause/resume/step/reset, and can hold
// each step until an external controller answered (`sear run --lcm-lockstep N`).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "runtime/run_tap.hpp"

namespace sear {

class Simulation;
struct ProjectDesc;

struct LcmOptions {
  std::optional<std::string> url;  // publish and subscribe on LCM at this URL; unset: no LCM
  std::string log_file;            // write every message published into this LCM event log; empty: none
  // Messages per simulated second. Each costs the run 5..10 us of CPU whatever its size (the UDP
  // send, and its copy looping back to this process, which listens on the same group), against
  // ~30 ms of wall time per simulated second of the default project: so about 0.03 % of the run
  // per message per simulated second. POSE and CLOCK, what a PC-side program follows, go at 50 Hz
  // (2 cm apart at 1 m/s; a controller that needs every step uses lockstep); the samples and
  // bytes, one message per device, are batched with their own time stamps at 10 Hz, which loses
  // nothing but latency. The default project then sends ~200 messages per simulated second.
  double rate_hz = 50;              // POSE and CLOCK; also how often DRIVE and CONTROL are taken
  double batch_rate_hz = 10;        // READING, TX/RX and CAN batches (and at every lockstep point)
  std::int64_t lockstep_every = 0;  // wait for each controlled robot's DRIVE every this many steps; 0: never
  double timeout_s = 5;             // host seconds a lockstep controller may stay silent
};

// The exit code of a run whose lockstep controller stopped answering.
inline constexpr int kLcmControllerGoneExitCode = 6;

struct LcmError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class LcmBridge : public RunTap {
 public:
  // Opens LCM and the log. Throws LcmError when either cannot be opened, or when lockstep is asked
  // for without LCM.
  explicit LcmBridge(const LcmOptions& options);
  ~LcmBridge() override;
  LcmBridge(const LcmBridge&) = delete;
  LcmBridge& operator=(const LcmBridge&) = delete;

  // A run (or a run started over by a reset) begins at t = 0 with this simulation. Throws LcmError
  // when lockstep is asked for and no robot is without an MCU.
  void start_run(Simulation& sim, const ProjectDesc& project);

  enum class Gate {
    Step,            // go on with the next step
    Stop,            // a stop was requested (Ctrl-C) while paused or waiting
    ControllerGone,  // lockstep: no answer within the timeout; failure() says which robot and step
    Reset,           // SEAR/CONTROL asked to start over at t = 0
  };
  // Before each step: takes what arrived, holds while paused, and at lockstep points publishes the
  // clock and waits for the controller; drive commands are applied to the robots here.
  Gate before_step();
  // After each step: publishes what is due.
  void after_step();
  // The run ended: the last clock, and whatever was batched, go out.
  void finish();
  const std::string& failure() const { return failure_; }

  void on_mcu_events(std::size_t mcu, const sear_event* events, std::size_t count) override {
    for (std::size_t i = 0; i < count; ++i) on_mcu_event(mcu, events[i]);
  }
  void on_mcu_event(std::size_t mcu, const sear_event& event);
  void on_sample(std::size_t mcu, std::size_t device, const sear_link_sample& sample) override;
  void on_wire_bytes(std::size_t mcu, std::size_t device, bool from_device, const serial_byte* bytes,
                     std::size_t count) override;
  void on_can_frame(std::size_t bus, const CanTransfer& transfer) override;

 private:
  struct State;
  std::unique_ptr<State> s_;
  std::string failure_;
};

}  // namespace sear
