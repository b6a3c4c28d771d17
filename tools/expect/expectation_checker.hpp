// Decides a scenario's expectations while a run goes on, from what the run shows its taps: console
// lines and pin levels from each MCU's events, UART bytes from events and device wires, regions
// and collisions from the world after each step, and MCU stops from the run loop.
// Events carry their own times (a UART byte is stamped with the end of its stop bit, possibly a
// quantum ahead); each is taken in time order only once the world has passed it, so a verdict
// never depends on when an event happened to be reported.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "expect/expectation.hpp"
#include "runtime/run_tap.hpp"
#include "runtime/simulation.hpp"

namespace sear {

enum class Verdict { Pending, Passed, Failed };

struct ExpectationResult {
  const Expectation* expectation = nullptr;  // into the Scenario the checker was made with
  Verdict verdict = Verdict::Pending;
  std::int64_t time_ns = 0;  // when it was decided
  std::string seen;          // for a failure: what was seen instead
};

// The world at the end of a step, as far as expectations look at it; on_step() fills it from the
// Simulation, tests build it by hand.
struct WorldMoment {
  std::int64_t time_ns = 0;
  std::vector<Eigen::Vector2d> robot_xy_m;      // chassis origins, as Simulation::robot(i)
  std::vector<CollisionEvent> new_collisions;  // since the previous moment
};

class ExpectationChecker final : public RunTap {
 public:
  // `scenario` and `project` must outlive the checker and have passed check_scenario().
  ExpectationChecker(const Scenario& scenario, const ProjectDesc& project);

  void on_mcu_events(std::size_t mcu, const sear_event* events, std::size_t count) override {
    for (std::size_t i = 0; i < count; ++i) on_mcu_event(mcu, events[i]);
  }
  void on_mcu_event(std::size_t mcu, const sear_event& event);
  void on_wire_bytes(std::size_t mcu, std::size_t device, bool from_device, const serial_byte* bytes,
                     std::size_t count) override;
  void on_step(const Simulation& sim) override;
  void advance(const WorldMoment& moment);
  // MCU `mcu` (as Lockstep::mcu(i)) stopped taking part at `time_ns` (the failure's time) for
  // `why` ("crashed with signal 11 (SIGSEGV)"). Not for MCUs shut down because the run ended.
  void mcu_stopped(std::size_t mcu, std::int64_t time_ns, std::string why);
  // The same by its "robot.mcu" id, as Lockstep::stops() names it; an unknown id is ignored.
  void mcu_stopped(const std::string& mcu, std::int64_t time_ns, std::string why);
  // The run ended at `end_ns`: what is still pending fails (or, for "never" kinds, passes) there.
  // An interrupted run (Ctrl-C, a closed viewer) decides only what was due by then: the rest
  // stays Pending, undecided, as its firmware was never given the time to meet it.
  void finish(std::int64_t end_ns, bool interrupted = false);

  // Every expectation is decided: the run may stop.
  bool decided() const;
  // Decided, and none failed.
  bool passed() const;
  const std::vector<ExpectationResult>& results() const { return results_; }

 private:
  struct PinState {
    bool output = false;
    int level = 0;
    int pwm = 0;  // duty 1..254 while a PWM waveform runs
  };
  struct Event {
    std::int64_t time_ns;
    std::uint8_t kind;  // SEAR_EVENT_*
    std::uint8_t index;
    std::uint32_t value;
  };
  struct Mcu {
    std::string id;
    int console_port = -1;
    std::vector<int> device_port;           // per McuDesc::devices: its UART port, or -1
    std::array<bool, 4> port_has_device{};  // rx comes from the device's wire, not from RX events
    std::vector<Event> pending;             // reported, not yet taken, in the order reported
    std::int64_t stop_ns = INT64_MAX;
    std::string stop_why;
    std::string line;
    std::int64_t line_time = 0;
    std::uint64_t lines = 0;
    std::string last_line;
    std::int64_t last_line_time = 0;
    std::array<PinState, SEAR_LINK_PINS> pins{};
  };
  struct Live {
    std::size_t mcu = SIZE_MAX;
    std::size_t robot = SIZE_MAX;
    double closest_m = INFINITY;  // region
    std::int64_t closest_ns = 0;
    bool pin_started = false;     // the level at `from` was right
    std::string window;           // the last bytes, as long as the UART pattern
    std::uint64_t counted = 0;    // UART bytes by the deadline
  };

  void take(std::size_t m, std::int64_t until_ns, bool inclusive);
  void apply(std::size_t m, const Event& e);
  void settle_pins(std::size_t m, std::int64_t time_ns);
  void end_line(std::size_t m);
  void settle(std::size_t m, std::int64_t known_ns);
  void resolve_stop(std::size_t m);
  std::string seen_by(std::size_t i, std::int64_t at_ns) const;
  std::string region_seen(std::size_t i) const;
  void pass(std::size_t i, std::int64_t time_ns);
  void fail(std::size_t i, std::int64_t time_ns, std::string seen);
  std::int64_t deadline(const Expectation& e) const;
  std::string pin_text(const PinState& p) const;

  const Scenario& scenario_;
  std::vector<Mcu> mcus_;
  std::vector<ExpectationResult> results_;
  std::vector<Live> live_;
  std::vector<std::vector<std::size_t>> by_mcu_;  // expectation indices per MCU
  std::int64_t world_ns_ = 0;  // the world's latest step end
  std::size_t collisions_seen_ = 0;
  std::size_t pending_ = 0;
};

// "expectation failed at 12.400 s: region rover circle (5, 5) r 1 before 30 s: the robot came ..."
std::string failure_text(const ExpectationResult& result);

}  // namespace sear
