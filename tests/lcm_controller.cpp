// A stand-in for a user's program on the other end of `sear run --lcm`, written against the
// generated C++ types as a user would:
//   lcm_controller drive URL ROBOT DUTY_LEFT DUTY_RIGHT SILENT_FROM
//     answers every lockstep CLOCK with a DRIVE of the given duties to motors "left" and "right",
//     until the clock reaches step SILENT_FROM (-1: never), then goes silent; prints
//     "clock STEP TIME_NS" for every clock answered, and "repeat STEP" for a clock seen twice;
//   lcm_controller control URL END_STEP
//     pauses a running simulation, watches it hold still, steps it 25 steps, resets it and lets
//     it run on to END_STEP; prints what the CLOCK said at each point;
//   lcm_controller ping URL CHANNEL
//     sends one empty message on CHANNEL and ends.
// It prints "ready" once subscribed, and ends (drive) when the run has been silent for 2 s.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <lcm/lcm-cpp.hpp>
#include <set>
#include <string>

#include "sear/lcm/sear/control_t.hpp"
#include "sear/lcm/sear/drive_t.hpp"
#include "sear/lcm/sear/sim_clock_t.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Driver {
  lcm::LCM* lcm;
  std::string drive_channel;
  double left, right;
  long long silent_from;
  std::set<long long> answered;

  void on_clock(const lcm::ReceiveBuffer*, const std::string&, const sear::sim_clock_t* m) {
    if (!m->awaiting_drive) return;
    if (silent_from >= 0 && m->step >= silent_from) return;
    if (!answered.insert(m->step).second) {
      std::printf("repeat %lld\n", static_cast<long long>(m->step));
      return;
    }
    sear::drive_t d;
    d.utime = 0;
    d.answers_step = m->step;
    d.count = 2;
    d.motor = {"left", "right"};
    d.mode = {sear::drive_t::DRIVE, sear::drive_t::DRIVE};
    d.duty = {left, right};
    lcm->publish(drive_channel, &d);
    std::printf("clock %lld %lld\n", static_cast<long long>(m->step), static_cast<long long>(m->time_ns));
  }
};

struct Watcher {
  sear::sim_clock_t last{};
  bool seen = false;
  void on_clock(const lcm::ReceiveBuffer*, const std::string&, const sear::sim_clock_t* m) {
    last = *m;
    seen = true;
  }
};

// Handles messages until `done` holds or the run has been silent for 2 s; false on silence.
template <class Done>
bool wait_for(lcm::LCM& lcm, Done done) {
  auto quiet_since = Clock::now();
  while (!done()) {
    if (lcm.handleTimeout(50) > 0)
      quiet_since = Clock::now();
    else if (Clock::now() - quiet_since > std::chrono::seconds(2))
      return false;
  }
  return true;
}

void send(lcm::LCM& lcm, std::int8_t command, std::int64_t steps = 0) {
  sear::control_t c;
  c.utime = 0;
  c.command = command;
  c.steps = steps;
  lcm.publish("SEAR/CONTROL", &c);
}

int control(lcm::LCM& lcm, long long end_step) {
  Watcher w;
  lcm.subscribe("SEAR/CLOCK", &Watcher::on_clock, &w);
  std::printf("ready\n");
  std::fflush(stdout);
  if (!wait_for(lcm, [&] { return w.seen && w.last.step >= 200; })) return 2;
  send(lcm, sear::control_t::PAUSE);
  if (!wait_for(lcm, [&] { return w.last.paused; })) return 3;
  const long long paused_at = w.last.step;
  std::printf("paused %lld\n", paused_at);
  // Held still: for 0.3 s no clock may say anything but this step.
  long long highest = paused_at;
  for (const auto until = Clock::now() + std::chrono::milliseconds(300); Clock::now() < until;)
    if (lcm.handleTimeout(20) > 0 && w.last.step > highest) highest = w.last.step;
  std::printf("held %lld\n", highest);
  send(lcm, sear::control_t::STEP, 25);
  if (!wait_for(lcm, [&] { return w.last.paused && w.last.step != paused_at; })) return 4;
  const long long stepped = w.last.step;
  std::printf("stepped %lld\n", stepped);
  send(lcm, sear::control_t::RESET);
  if (!wait_for(lcm, [&] { return w.last.step < stepped; })) return 5;
  std::printf("reset %lld %lld paused %d\n", static_cast<long long>(w.last.step),
              static_cast<long long>(w.last.time_ns), w.last.paused ? 1 : 0);
  send(lcm, sear::control_t::RESUME);
  wait_for(lcm, [&] { return w.last.step >= end_step; });
  std::printf("ended %lld\n", static_cast<long long>(w.last.step));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return 1;
  const std::string mode = argv[1];
  lcm::LCM lcm(argv[2]);
  if (!lcm.good()) return 1;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  if (mode == "control" && argc == 4) return control(lcm, std::atoll(argv[3]));
  if (mode == "ping" && argc == 4) return lcm.publish(argv[3], "", 0) == 0 ? 0 : 1;
  if (mode != "drive" || argc != 7) return 1;
  Driver d{&lcm, std::string("SEAR/") + argv[3] + "/DRIVE", std::atof(argv[4]), std::atof(argv[5]), std::atoll(argv[6]),
           {}};
  lcm.subscribe("SEAR/CLOCK", &Driver::on_clock, &d);
  std::printf("ready\n");
  std::fflush(stdout);
  wait_for(lcm, [] { return false; });
  return 0;
}
