#include "lcm/lcm_bridge.hpp"

#include <fmt/format.h>
#include <lcm/eventlog.h>
#include <lcm/lcm.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <set>
#include <vector>

#include "lcm/lcm_channels.hpp"
#include "lcm/reading_meaning.hpp"
#include "runtime/can_bus.hpp"
#include "runtime/simulation.hpp"
#include "runtime/stop_request.hpp"
#include "runtime/while_waiting.hpp"
#include "scene/device_kind.hpp"
#include "sear/lcm/sear_can_t.h"
#include "sear/lcm/sear_control_t.h"
#include "sear/lcm/sear_drive_t.h"
#include "sear/lcm/sear_outputs_t.h"
#include "sear/lcm/sear_pose_t.h"
#include "sear/lcm/sear_reading_t.h"
#include "sear/lcm/sear_serial_t.h"
#include "sear/lcm/sear_sim_clock_t.h"

namespace sear {
namespace {

using Clock = std::chrono::steady_clock;

// Where the run's messages go: the LCM instance, the event log, or both. Each message is encoded
// once, into a buffer kept between messages (no allocation once it has grown to the largest), and
// the same bytes go to both.
class Sink {
 public:
  explicit Sink(const LcmOptions& o) {
    if (o.url) {
      lcm_ = lcm_create(o.url->c_str());
      if (!lcm_) throw LcmError(fmt::format("sear: cannot open LCM at '{}'", *o.url));
    }
    if (!o.log_file.empty()) {
      log_ = lcm_eventlog_create(o.log_file.c_str(), "w");
      if (!log_) {
        if (lcm_) lcm_destroy(lcm_);
        throw LcmError(fmt::format("sear: cannot write the LCM log '{}'", o.log_file));
      }
    }
  }
  ~Sink() {
    if (log_) lcm_eventlog_destroy(log_);
    if (lcm_) lcm_destroy(lcm_);
  }
  lcm_t* lcm() const { return lcm_; }

  // `encode` and `size` are lcm-gen's functions for T. `logged`, when given, goes to the log in
  // place of `msg`: the log holds only what the same project and seed always give.
  template <class T>
  void publish(const std::string& channel, const T& msg, int (*size)(const T*),
               int (*encode)(void*, int, int, const T*), std::int64_t utime, const T* logged = nullptr) {
    const int n = size(&msg);
    if (buffer_.size() < static_cast<std::size_t>(n)) buffer_.resize(static_cast<std::size_t>(n) * 2);
    if (encode(buffer_.data(), 0, n, &msg) != n) return;  // cannot happen for a message sized by `size`
    if (lcm_) lcm_publish(lcm_, channel.c_str(), buffer_.data(), static_cast<unsigned>(n));
    if (log_ && logged && encode(buffer_.data(), 0, n, logged) != n) return;
    if (log_) {
      lcm_eventlog_event_t e{};
      e.eventnum = events_++;
      e.timestamp = utime;  // sim time: lcm-logplayer replays the run at its simulated pace
      e.channellen = static_cast<std::int32_t>(channel.size());
      e.datalen = n;
      e.channel = const_cast<char*>(channel.c_str());
      e.data = buffer_.data();
      lcm_eventlog_write_event(log_, &e);
    }
  }

 private:
  lcm_t* lcm_ = nullptr;
  lcm_eventlog_t* log_ = nullptr;
  std::vector<std::uint8_t> buffer_;
  std::int64_t events_ = 0;
};

std::int64_t utime_of(std::int64_t ns) { return ns / 1000; }

// One device's READING batch and its UART byte batches.
struct DeviceOut {
  std::string device_name, kind;
  std::string reading_channel, tx_channel, rx_channel;
  std::vector<char*> quantity, unit;
  int values = 0;
  std::vector<std::int64_t> sample_time, sample_index;
  std::vector<double> flat;  // sample_count * values
  std::vector<double*> rows;
  struct Bytes {
    std::vector<std::int64_t> end_ns;
    std::vector<std::int32_t> baud;
    std::vector<std::uint8_t> data;
  } tx, rx;
};

struct PinOut {
  std::int8_t drive = -1;  // sear_outputs_t LEVEL/PWM/SERVO; -1: never driven
  double value = 0;
  bool operator==(const PinOut& o) const { return drive == o.drive && value == o.value; }
};

struct McuOut {
  std::size_t robot;
  std::string robot_name, mcu_name, outputs_channel;
  std::vector<DeviceOut> devices;
  std::array<PinOut, SEAR_LINK_PINS> pins{}, published{};
  std::array<bool, SEAR_LINK_PINS> output{};  // pin_mode OUTPUT: a level written to it is driven
  // Some pin had an event this step. A chip select or trigger pulses within a step and ends
  // where it began, so what is sent is decided against what was sent last.
  bool touched = false;
};

struct RobotIo {
  std::string name, pose_channel, drive_channel;
  bool has_mcu = false;
  bool warned_mcu = false;
  std::set<std::string> warned_motors;
  std::int64_t answered_step = -1;  // the last lockstep step its controller answered
};

}  // namespace

struct LcmBridge::State {
  explicit State(const LcmOptions& o) : options(o), sink(o) {}

  LcmOptions options;
  Sink sink;
  Simulation* sim = nullptr;
  std::vector<RobotIo> robots;
  std::vector<McuOut> mcus;
  std::vector<std::string> can_names, can_channels;
  std::vector<std::vector<sear_can_frame_t>> can_frames;
  std::vector<lcm_subscription_t*> subscriptions;
  struct DriveContext {
    State* state;
    std::size_t robot;
  };
  std::vector<std::unique_ptr<DriveContext>> drive_contexts;  // what each DRIVE subscription is told
  std::int64_t publish_every = 1;                             // steps between POSE and CLOCK messages
  std::int64_t batch_every = 1;                               // steps between READING, TX/RX and CAN batches
  std::int64_t last_pose_step = -1, last_clock_step = -1;
  bool paused = false;
  std::int64_t steps_left = -1;  // STEP n: steps still to take before pausing; -1: not stepping
  bool reset = false;
  Clock::time_point wall_start;

  std::int64_t step() const { return sim->time_ns() / sim->step_ns(); }

  void publish_clock(bool awaiting_drive = false) {
    const std::int64_t t = sim->time_ns();
    const double wall = std::chrono::duration<double>(Clock::now() - wall_start).count();
    sear_sim_clock_t m{};
    m.utime = utime_of(t);
    m.time_ns = t;
    m.step = step();
    m.step_ns = sim->step_ns();
    m.paused = paused;
    m.lockstep_every = static_cast<std::int32_t>(options.lockstep_every);
    m.awaiting_drive = awaiting_drive;
    m.real_time_factor = wall > 0 ? sim->time_s() / wall : 0;
    sear_sim_clock_t logged = m;
    logged.real_time_factor = 0;  // the host's speed, not the run's: 0 in the log
    sink.publish(kLcmClockChannel, m, sear_sim_clock_t_encoded_size, sear_sim_clock_t_encode, m.utime, &logged);
    last_clock_step = m.step;
  }

  void publish_poses() {
    const std::int64_t t = sim->time_ns();
    for (std::size_t r = 0; r < robots.size(); ++r) {
      const VehicleState s = sim->robot_state(r);
      sear_pose_t m{};
      m.utime = utime_of(t);
      m.time_ns = t;
      m.robot = const_cast<char*>(robots[r].name.c_str());
      const Eigen::Quaterniond q = Eigen::AngleAxisd(s.roll_pitch_yaw[2], Eigen::Vector3d::UnitZ()) *
                                   Eigen::AngleAxisd(s.roll_pitch_yaw[1], Eigen::Vector3d::UnitY()) *
                                   Eigen::AngleAxisd(s.roll_pitch_yaw[0], Eigen::Vector3d::UnitX());
      for (int i = 0; i < 3; ++i) {
        m.position[i] = s.position_m[i];
        m.roll_pitch_yaw[i] = s.roll_pitch_yaw[i];
        m.velocity[i] = s.velocity_mps[i];
        m.angular_velocity[i] = s.angular_velocity[i];
      }
      m.orientation[0] = q.w();
      m.orientation[1] = q.x();
      m.orientation[2] = q.y();
      m.orientation[3] = q.z();
      m.forward_speed = s.forward_speed_mps;
      sink.publish(robots[r].pose_channel, m, sear_pose_t_encoded_size, sear_pose_t_encode, m.utime);
    }
    last_pose_step = step();
  }

  void publish_bytes(const McuOut& mcu, DeviceOut& d, bool from_device) {
    DeviceOut::Bytes& b = from_device ? d.tx : d.rx;
    if (b.data.empty()) return;
    const std::int64_t t = sim->time_ns();
    sear_serial_t m{};
    m.utime = utime_of(t);
    m.time_ns = t;
    m.robot = const_cast<char*>(mcu.robot_name.c_str());
    m.mcu = const_cast<char*>(mcu.mcu_name.c_str());
    m.device = const_cast<char*>(d.device_name.c_str());
    m.from_device = from_device;
    m.count = static_cast<std::int32_t>(b.data.size());
    m.end_ns = b.end_ns.data();
    m.baud = b.baud.data();
    m.data = b.data.data();
    sink.publish(from_device ? d.tx_channel : d.rx_channel, m, sear_serial_t_encoded_size, sear_serial_t_encode,
                 m.utime);
    b.end_ns.clear();  // clear() keeps the capacity: the next batch allocates nothing
    b.baud.clear();
    b.data.clear();
  }

  void publish_readings() {
    const std::int64_t t = sim->time_ns();
    for (McuOut& mcu : mcus)
      for (DeviceOut& d : mcu.devices) {
        publish_bytes(mcu, d, true);
        publish_bytes(mcu, d, false);
        if (d.sample_time.empty()) continue;
        d.rows.clear();
        for (std::size_t i = 0; i < d.sample_time.size(); ++i)
          d.rows.push_back(d.flat.data() + i * static_cast<std::size_t>(d.values));
        sear_reading_t m{};
        m.utime = utime_of(t);
        m.time_ns = t;
        m.robot = const_cast<char*>(mcu.robot_name.c_str());
        m.mcu = const_cast<char*>(mcu.mcu_name.c_str());
        m.device = const_cast<char*>(d.device_name.c_str());
        m.kind = const_cast<char*>(d.kind.c_str());
        m.value_count = static_cast<std::int8_t>(d.values);
        m.quantity = d.quantity.data();
        m.unit = d.unit.data();
        m.sample_count = static_cast<std::int32_t>(d.sample_time.size());
        m.sample_time_ns = d.sample_time.data();
        m.sample_index = d.sample_index.data();
        m.value = d.rows.data();
        sink.publish(d.reading_channel, m, sear_reading_t_encoded_size, sear_reading_t_encode, m.utime);
        d.sample_time.clear();
        d.sample_index.clear();
        d.flat.clear();
      }
  }

  void publish_can() {
    const std::int64_t t = sim->time_ns();
    for (std::size_t b = 0; b < can_frames.size(); ++b) {
      if (can_frames[b].empty()) continue;
      sear_can_t m{};
      m.utime = utime_of(t);
      m.time_ns = t;
      m.bus = const_cast<char*>(can_names[b].c_str());
      m.count = static_cast<std::int32_t>(can_frames[b].size());
      m.frames = can_frames[b].data();
      sink.publish(can_channels[b], m, sear_can_t_encoded_size, sear_can_t_encode, m.utime);
      can_frames[b].clear();
    }
  }

  void publish_outputs() {
    const std::int64_t t = sim->time_ns();
    std::array<std::int16_t, SEAR_LINK_PINS> pin{};
    std::array<std::int8_t, SEAR_LINK_PINS> drive{};
    std::array<double, SEAR_LINK_PINS> value{};
    for (McuOut& mcu : mcus) {
      if (!mcu.touched) continue;
      mcu.touched = false;
      if (mcu.pins == mcu.published) continue;
      mcu.published = mcu.pins;
      std::int16_t n = 0;
      for (std::size_t p = 0; p < mcu.pins.size(); ++p)
        if (mcu.pins[p].drive >= 0) {
          pin[n] = static_cast<std::int16_t>(p);
          drive[n] = mcu.pins[p].drive;
          value[n] = mcu.pins[p].value;
          ++n;
        }
      sear_outputs_t m{};
      m.utime = utime_of(t);
      m.time_ns = t;
      m.robot = const_cast<char*>(mcu.robot_name.c_str());
      m.mcu = const_cast<char*>(mcu.mcu_name.c_str());
      m.count = n;
      m.pin = pin.data();
      m.drive = drive.data();
      m.value = value.data();
      sink.publish(mcu.outputs_channel, m, sear_outputs_t_encoded_size, sear_outputs_t_encode, m.utime);
    }
  }

  void on_drive(std::size_t r, const sear_drive_t& m) {
    RobotIo& io = robots[r];
    if (io.has_mcu) {
      if (!io.warned_mcu)
        fmt::print(stderr, "sear: robot '{}' has an MCU, which drives its motors: {} is ignored\n", io.name,
                   io.drive_channel);
      io.warned_mcu = true;
      return;
    }
    if (options.lockstep_every > 0 && m.answers_step >= 0) {
      // An answer to a clock already answered, or to one not yet sent, would let time jump for
      // the controller: only the awaited step's answer counts.
      const std::int64_t awaited = step();
      if (m.answers_step != awaited || io.answered_step == awaited) return;
      io.answered_step = awaited;
    }
    Vehicle& v = sim->robot(r);
    for (int i = 0; i < m.count; ++i) {
      const int motor = v.motor_index(m.motor[i]);
      if (motor < 0) {
        if (io.warned_motors.insert(m.motor[i]).second)
          fmt::print(stderr, "sear: robot '{}' has no motor '{}' ({} ignores it)\n", io.name, m.motor[i],
                     io.drive_channel);
        continue;
      }
      DcMotorCommand c;
      if (m.mode[i] == SEAR_DRIVE_T_BRAKE) {
        c.direction = MotorDirection::Brake;
      } else if (m.mode[i] == SEAR_DRIVE_T_DRIVE && std::isfinite(m.duty[i])) {
        c.direction = m.duty[i] < 0 ? MotorDirection::Reverse : MotorDirection::Forward;
        c.duty = std::min(1.0, std::fabs(m.duty[i]));
      }  // COAST, or anything not understood, lets the motor go
      v.command_motor(static_cast<std::size_t>(motor), c);
    }
  }

  void on_control(const sear_control_t& m) {
    switch (m.command) {
      case SEAR_CONTROL_T_PAUSE:
        if (!paused) {
          paused = true;
          publish_clock();
        }
        steps_left = -1;
        break;
      case SEAR_CONTROL_T_RESUME:
        paused = false;
        steps_left = -1;
        break;
      case SEAR_CONTROL_T_STEP:
        if (m.steps > 0) {
          paused = false;
          steps_left = m.steps;
        }
        break;
      case SEAR_CONTROL_T_RESET:
        reset = true;
        break;
      default:
        break;
    }
  }

  // Takes what has arrived; waits up to timeout_ms for the first message when there is none.
  void handle(int timeout_ms) {
    lcm_t* lcm = sink.lcm();
    if (!lcm) return;
    // One wait, then whatever else is already queued, without waiting again.
    if (lcm_handle_timeout(lcm, timeout_ms) <= 0) return;
    while (lcm_handle_timeout(lcm, 0) > 0) {
    }
  }
};

LcmBridge::LcmBridge(const LcmOptions& options) {
  if (options.lockstep_every > 0 && !options.url)
    throw LcmError("sear: --lcm-lockstep needs --lcm: the controller answers over LCM");
  s_ = std::make_unique<State>(options);
  if (lcm_t* lcm = s_->sink.lcm()) {
    s_->subscriptions.push_back(lcm_subscribe(
        lcm, kLcmControlChannel,
        [](const lcm_recv_buf_t* rbuf, const char*, void* user) {
          sear_control_t m{};
          if (sear_control_t_decode(rbuf->data, 0, static_cast<int>(rbuf->data_size), &m) < 0) return;
          static_cast<State*>(user)->on_control(m);
          sear_control_t_decode_cleanup(&m);
        },
        s_.get()));
  }
}

LcmBridge::~LcmBridge() {
  if (lcm_t* lcm = s_->sink.lcm())
    for (auto* sub : s_->subscriptions) lcm_unsubscribe(lcm, sub);
}

void LcmBridge::start_run(Simulation& sim, const ProjectDesc& project) {
  State& s = *s_;
  s.sim = &sim;
  s.wall_start = Clock::now();
  s.reset = false;
  s.last_pose_step = s.last_clock_step = -1;
  const auto steps_per = [&](double hz) {
    return std::max<std::int64_t>(1, std::llround(1e9 / hz / static_cast<double>(sim.step_ns())));
  };
  s.publish_every = steps_per(s.options.rate_hz);
  s.batch_every = steps_per(s.options.batch_rate_hz);
  const bool first = s.robots.empty();
  if (first) {
    for (std::size_t r = 0; r < project.robots.size(); ++r) {
      const RobotDesc& rd = project.robots[r];
      RobotIo io;
      io.name = rd.name;
      io.pose_channel = lcm_pose_channel(rd.name);
      io.drive_channel = lcm_drive_channel(rd.name);
      io.has_mcu = !rd.mcus.empty();
      s.robots.push_back(std::move(io));
      for (const McuDesc& md : rd.mcus) {
        McuOut mo;
        mo.robot = r;
        mo.robot_name = rd.name;
        mo.mcu_name = md.name;
        mo.outputs_channel = lcm_outputs_channel(rd.name, md.name);
        for (const DeviceDesc& dd : md.devices) {
          DeviceOut d;
          d.device_name = dd.name;
          d.kind = dd.kind ? dd.kind->element : "";
          d.reading_channel = lcm_reading_channel(rd.name, md.name, dd.name);
          d.tx_channel = lcm_serial_channel(rd.name, md.name, dd.name, true);
          d.rx_channel = lcm_serial_channel(rd.name, md.name, dd.name, false);
          const ReadingMeaning& meaning = reading_meaning(d.kind);
          for (const char* q : meaning.quantity) d.quantity.push_back(const_cast<char*>(q));
          for (const char* u : meaning.unit) d.unit.push_back(const_cast<char*>(u));
          d.values = static_cast<int>(d.quantity.size());
          mo.devices.push_back(std::move(d));
        }
        s.mcus.push_back(std::move(mo));
      }
    }
    for (const auto& bus : project.can_buses) {
      s.can_names.push_back(bus.name);
      s.can_channels.push_back(lcm_can_channel(bus.name));
    }
    s.can_frames.resize(project.can_buses.size());
    if (lcm_t* lcm = s.sink.lcm())
      for (std::size_t r = 0; r < s.robots.size(); ++r) {
        s.drive_contexts.push_back(std::make_unique<State::DriveContext>(State::DriveContext{&s, r}));
        s.subscriptions.push_back(lcm_subscribe(
            lcm, s.robots[r].drive_channel.c_str(),
            [](const lcm_recv_buf_t* rbuf, const char*, void* user) {
              auto* c = static_cast<State::DriveContext*>(user);
              sear_drive_t m{};
              if (sear_drive_t_decode(rbuf->data, 0, static_cast<int>(rbuf->data_size), &m) < 0) return;
              c->state->on_drive(c->robot, m);
              sear_drive_t_decode_cleanup(&m);
            },
            s.drive_contexts.back().get()));
      }
    if (s.options.lockstep_every > 0 &&
        std::none_of(s.robots.begin(), s.robots.end(), [](const RobotIo& io) { return !io.has_mcu; }))
      throw LcmError(
          "sear: --lcm-lockstep waits for the DRIVE of robots without an MCU, and every robot of this project has one");
  } else {
    // Started over: what was batched belonged to the run before.
    for (McuOut& m : s.mcus) {
      m.pins = m.published = {};
      m.output = {};
      m.touched = false;
      for (DeviceOut& d : m.devices) {
        d.sample_time.clear();
        d.sample_index.clear();
        d.flat.clear();
        d.tx = {};
        d.rx = {};
      }
    }
    for (auto& f : s.can_frames) f.clear();
  }
  for (RobotIo& io : s.robots) io.answered_step = -1;
  s.publish_poses();
  if (s.options.lockstep_every <= 0) s.publish_clock();  // else before_step sends step 0's, awaiting
}

LcmBridge::Gate LcmBridge::before_step() {
  State& s = *s_;
  const std::int64_t k = s.step();
  // Looking costs a system call; a step is often shorter than that is worth.
  if (k % s.publish_every == 0) s.handle(0);
  for (;;) {
    if (s.reset) return Gate::Reset;
    if (stop_requested()) return Gate::Stop;
    if (!s.paused) break;
    while_waiting();
    s.handle(100);  // short, so that Ctrl-C is seen within a tenth of a second
  }
  if (s.options.lockstep_every <= 0 || k % s.options.lockstep_every != 0) return Gate::Step;

  // The controller sees the world of step k (its POSE and readings, then the CLOCK it answers).
  if (s.last_pose_step != k) s.publish_poses();
  s.publish_readings();
  s.publish_can();
  s.publish_clock(true);
  const auto deadline = Clock::now() + std::chrono::duration<double>(s.options.timeout_s);
  // A controller started after this clock went out (udpm keeps nothing for late subscribers)
  // still gets it: it is sent again every second of waiting; answers after the first are ignored.
  auto repeat_at = Clock::now() + std::chrono::seconds(1);
  for (;;) {
    const RobotIo* waiting = nullptr;
    for (const RobotIo& io : s.robots)
      if (!io.has_mcu && io.answered_step != k) {
        waiting = &io;
        break;
      }
    if (!waiting) return Gate::Step;
    if (s.reset) return Gate::Reset;
    if (stop_requested()) return Gate::Stop;
    while_waiting();
    const double left_s = std::chrono::duration<double>(deadline - Clock::now()).count();
    if (left_s <= 0) {
      failure_ = fmt::format("no DRIVE for robot '{}' answering step {} within {:g} s: the controller is gone",
                             waiting->name, k, s.options.timeout_s);
      return Gate::ControllerGone;
    }
    if (Clock::now() >= repeat_at) {
      s.publish_clock(true);
      repeat_at += std::chrono::seconds(1);
    }
    s.handle(static_cast<int>(std::clamp(left_s * 1000.0, 1.0, 100.0)));
  }
}

void LcmBridge::after_step() {
  State& s = *s_;
  const std::int64_t k = s.step();
  if (k % s.publish_every == 0) s.publish_poses();
  if (k % s.batch_every == 0) {
    s.publish_readings();
    s.publish_can();
  }
  s.publish_outputs();
  bool stepped_to_pause = false;
  if (s.steps_left > 0 && --s.steps_left == 0) {
    s.steps_left = -1;
    s.paused = stepped_to_pause = true;
  }
  // At a lockstep point the clock goes out once, before the wait, saying so.
  const bool lockstep_point = s.options.lockstep_every > 0 && k % s.options.lockstep_every == 0;
  if (stepped_to_pause || (k % s.publish_every == 0 && !lockstep_point)) s.publish_clock();
}

void LcmBridge::finish() {
  State& s = *s_;
  if (!s.sim) return;
  s.publish_readings();
  s.publish_can();
  s.publish_outputs();
  if (s.last_pose_step != s.step()) s.publish_poses();
  if (s.last_clock_step != s.step()) s.publish_clock();
}

void LcmBridge::on_mcu_event(std::size_t mcu, const sear_event& e) {
  if (mcu >= s_->mcus.size() || e.index >= SEAR_LINK_PINS) return;
  McuOut& m = s_->mcus[mcu];
  PinOut now;
  switch (e.kind) {
    case SEAR_EVENT_PIN_MODE:
      // An input drives nothing (a level written to it sets its pull-up); an output's level
      // follows as a PIN event.
      m.output[e.index] = e.value == 1;  // OUTPUT
      if (m.output[e.index]) return;
      break;
    case SEAR_EVENT_PIN:
      if (!m.output[e.index]) return;
      now = {SEAR_OUTPUTS_T_LEVEL, e.value ? 1.0 : 0.0};
      break;
    case SEAR_EVENT_PWM:
      now = {SEAR_OUTPUTS_T_PWM, e.value / 255.0};
      break;
    case SEAR_EVENT_SERVO:
      now = {SEAR_OUTPUTS_T_SERVO, e.value * 1e-6};
      break;
    default:
      return;
  }
  m.pins[e.index] = now;
  m.touched = true;
}

void LcmBridge::on_sample(std::size_t mcu, std::size_t device, const sear_link_sample& sample) {
  if (mcu >= s_->mcus.size() || device >= s_->mcus[mcu].devices.size()) return;
  DeviceOut& d = s_->mcus[mcu].devices[device];
  d.sample_time.push_back(sample.time_ns);
  d.sample_index.push_back(static_cast<std::int64_t>(sample.index));
  d.flat.insert(d.flat.end(), sample.value, sample.value + d.values);
}

void LcmBridge::on_wire_bytes(std::size_t mcu, std::size_t device, bool from_device, const serial_byte* bytes,
                              std::size_t count) {
  if (mcu >= s_->mcus.size() || device >= s_->mcus[mcu].devices.size()) return;
  DeviceOut& d = s_->mcus[mcu].devices[device];
  DeviceOut::Bytes& b = from_device ? d.tx : d.rx;
  for (std::size_t i = 0; i < count; ++i) {
    b.end_ns.push_back(bytes[i].end_ns);
    b.baud.push_back(static_cast<std::int32_t>(bytes[i].baud));
    b.data.push_back(bytes[i].value);
  }
}

void LcmBridge::on_can_frame(std::size_t bus, const CanTransfer& transfer) {
  if (bus >= s_->can_frames.size()) return;
  sear_can_frame_t f{};
  f.start_ns = transfer.start_ns;
  f.end_ns = transfer.end_ns;
  f.node = static_cast<std::int32_t>(transfer.node);
  f.id = static_cast<std::int32_t>(transfer.frame.id);
  f.extended = transfer.frame.extended;
  f.remote = transfer.frame.remote;
  f.dlc = static_cast<std::int8_t>(transfer.frame.dlc);
  std::copy(transfer.frame.data.begin(), transfer.frame.data.end(), f.data);
  f.tag = static_cast<std::int64_t>(transfer.tag);
  f.acked = transfer.acked;
  s_->can_frames[bus].push_back(f);
}

}  // namespace sear
