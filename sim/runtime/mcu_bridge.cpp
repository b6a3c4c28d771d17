#include "runtime/mcu_bridge.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sear {
namespace {

// Independent noise streams per device from one run seed (splitmix64's finaliser).
std::uint64_t mix(std::uint64_t seed, std::uint64_t salt) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ull * (salt + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

RangeBeam beam_of(const IrRangerDesc& s) {
  RangeBeam b;
  b.position_m = s.position_m;
  b.yaw_rad = s.yaw_rad;
  b.pitch_rad = s.pitch_rad;
  b.half_angle_rad = s.half_angle_rad;
  b.resolution_rad = s.resolution_rad;
  b.max_range_m = s.max_range_m;
  return b;
}

// A lever is felt along its whole width: parallel rays at most 2 cm apart, each its reach long.
std::vector<RangeSensor> lever_rays(const BumpSwitchDesc& b) {
  const int n = std::max(1, static_cast<int>(std::ceil(b.width_m / 0.02))) + 1;
  const Eigen::Vector3d across(-std::sin(b.yaw_rad), std::cos(b.yaw_rad), 0);
  std::vector<RangeSensor> rays;
  for (int i = 0; i < n; ++i) {
    RangeBeam beam;
    beam.position_m = b.position_m + across * (b.width_m * (static_cast<double>(i) / (n - 1) - 0.5));
    beam.yaw_rad = b.yaw_rad;
    beam.max_range_m = b.reach_m;
    rays.emplace_back(beam);
  }
  return rays;
}

std::int64_t call_cost_ns(const McuDesc& d) { return std::llround(d.hal_call_cycles * 1e9 / d.clock_hz); }

}  // namespace

McuBridge::McuBridge(const McuDesc& desc, std::string id, Vehicle& vehicle, std::uint64_t seed,
                     const std::string& host_log, const McuRunOptions& options)
    : desc_(desc), id_(std::move(id)), vehicle_(vehicle), seed_(seed) {
  for (const auto& s : desc_.rangers) {
    rangers_.emplace_back(beam_of(s));
    ranger_period_ns_.push_back(std::llround(s.period_s * 1e9));
  }
  for (const auto& b : desc_.bumps) bumps_.emplace_back(lever_rays(b));
  receive_next_.assign(desc_.uarts.size(), 0);
  McuProcessOptions process;
  process.hang_timeout_s = options.hang_timeout_s;
  process.call_cost_ns = call_cost_ns(desc_);
  process.max_file_bytes = options.max_file_bytes;
  process_ = std::make_unique<McuProcess>(desc_.firmware_executable, host_log, process, &McuBridge::setup_link, this);
}

void McuBridge::setup_link(sear_link& link, const void* context) {
  const auto& self = *static_cast<const McuBridge*>(context);
  const McuDesc& d = self.desc_;
  link.hal_call_cost_ns = call_cost_ns(d);
  link.avcc_v = d.avcc_v;
  link.aref_v = d.aref_v;
  if (d.rangers.size() + d.bumps.size() > SEAR_LINK_MAX_INPUTS)  // the loader already said where
    throw std::runtime_error(fmt::format("mcu {}: more than {} inputs", self.id_, SEAR_LINK_MAX_INPUTS));
  std::uint32_t n = 0;
  for (const auto& s : d.rangers) {
    sear_link_input& in = link.inputs[n];
    in.kind = s.model == IrRangerDesc::Model::Gp2d12 ? SEAR_INPUT_GP2D12 : SEAR_INPUT_GP2D15;
    in.target = static_cast<std::uint32_t>(s.model == IrRangerDesc::Model::Gp2d12 ? s.adc_channel : s.pin);
    in.seed = mix(self.seed_, n);
    in.noise_sd = s.noise_sd_v;
    in.switch_distance_m = s.switch_distance_m;
    in.hysteresis_m = s.hysteresis_m;
    ++n;
  }
  for (const auto& b : d.bumps) {
    link.inputs[n].kind = SEAR_INPUT_SWITCH;
    link.inputs[n].target = static_cast<std::uint32_t>(b.pin);
    ++n;
  }
  link.input_count = n;
  for (const auto& u : d.uarts)
    if (u.loopback) link.uart_loopback_mask |= 1u << u.port;
}

void McuBridge::add_sample(std::int64_t time_ns, std::uint64_t index, std::uint32_t input, double value) {
  if (samples_.size() == SEAR_LINK_MAX_SAMPLES) return;  // more than a quantum can hold: sensors run slower
  samples_.push_back({time_ns, index, input, 0, value});
}

void McuBridge::begin_quantum(const PhysicsWorld& physics, std::int64_t t0, std::int64_t t1) {
  if (process_->failure()) return;
  sear_link& link = process_->link();
  // Samples and counts are put together here and copied into the link once, last: a firmware (or
  // anything it forked) can write the link at any time, so nothing the simulator sorts or
  // indexes with is read back from it.
  samples_.clear();
  std::uint32_t rx_count = 0;
  const dBodyID chassis = vehicle_.chassis_body();
  const int self = vehicle_.entity();
  // Rangers measure on their own cycle, k * period; the world between steps is taken as it is at
  // the step's start. Samples go in time order, as the firmware applies them.
  std::uint32_t input = 0;
  for (std::size_t i = 0; i < rangers_.size(); ++i, ++input) {
    const std::int64_t period = ranger_period_ns_[i];
    for (std::int64_t k = (t0 + period - 1) / period; k * period < t1; ++k) {
      const RangeReading r = rangers_[i].measure(physics, chassis, self);
      add_sample(k * period, static_cast<std::uint64_t>(k), input, r.hit ? r.distance_m : INFINITY);
    }
  }
  for (const auto& lever : bumps_) {
    const bool closed = lever.any_hit(physics, chassis, self);  // one search of the world per lever
    add_sample(t0, 0, input++, closed ? 1.0 : 0.0);
  }
  std::stable_sort(samples_.begin(), samples_.end(),
                   [](const sear_link_sample& a, const sear_link_sample& b) { return a.time_ns < b.time_ns; });
  // Captured bytes due in this quantum (the link holds the most any step can bring).
  for (std::size_t u = 0; u < desc_.uarts.size(); ++u) {
    const auto& bytes = desc_.uarts[u].receive;
    std::size_t& next = receive_next_[u];
    for (; next < bytes.size() && bytes[next].time_ns < t1 && rx_count < SEAR_LINK_MAX_RX; ++next) {
      sear_link_rx& rx = link.rx[rx_count++];
      rx.time_ns = bytes[next].time_ns;
      rx.port = static_cast<std::uint8_t>(desc_.uarts[u].port);
      rx.byte = bytes[next].byte;
    }
  }
  std::copy(samples_.begin(), samples_.end(), link.samples);
  link.sample_count = static_cast<std::uint32_t>(samples_.size());
  link.rx_count = rx_count;
  process_->start_quantum(t1);
}

void McuBridge::drain(std::size_t index, McuListener& listener) {
  // Each event has passed the link's checks: a firmware that scribbled over its queue is stopped
  // at the first bad one, and nothing it made up reaches the pins, the motors or a file.
  for (const sear_event& e : process_->events()) {
    switch (e.kind) {
      case SEAR_EVENT_PIN_MODE:
        pin_output_[e.index] = e.value == 1;  // OUTPUT
        break;
      case SEAR_EVENT_PIN:
        pin_drive_[e.index] = e.value ? 255 : 0;
        break;
      case SEAR_EVENT_PWM:
        pin_drive_[e.index] = static_cast<int>(e.value);
        break;
      case SEAR_EVENT_SERVO:
        servo_pulse_us_[e.index] = static_cast<int>(e.value);
        break;
      default:
        break;
    }
    listener.on_event(index, e);
  }
}

void McuBridge::command_actuators() {
  const auto drive = [&](int pin) { return pin >= 0 && pin_output_[pin] ? pin_drive_[pin] : 0; };
  for (const auto& m : desc_.motors) {
    const int motor = vehicle_.motor_index(m.motor);
    DcMotorCommand c;
    c.duty = drive(m.pwm_pin) / 255.0;
    const bool forward = (drive(m.dir_pin) >= 128) != m.reversed;
    c.direction = forward ? MotorDirection::Forward : MotorDirection::Reverse;
    if (m.brake_pin >= 0 && drive(m.brake_pin) >= 128) {
      c.direction = MotorDirection::Brake;
      c.duty = 0;
    }
    vehicle_.command_motor(static_cast<std::size_t>(motor), c);
  }
  for (const auto& s : desc_.servos)  // 0: no pulses, so the servo does not hold
    vehicle_.command_servo(static_cast<std::size_t>(vehicle_.servo_index(s.servo)), servo_pulse_us_[s.pin]);
}

McuBridge::Outcome McuBridge::finish_quantum(std::size_t index, McuListener& listener) {
  for (;;) {
    const McuProcess::Turn turn = process_->wait();
    if (turn == McuProcess::Turn::Interrupted) return Outcome::Interrupted;
    drain(index, listener);  // whatever it wrote before stopping is kept too
    if (turn == McuProcess::Turn::Drain && !process_->failure()) {
      process_->resume();
      continue;
    }
    if (turn == McuProcess::Turn::Stopped || process_->failure()) {
      release_actuators();
      listener.on_stop(index, process_->failure()->time_ns);
      return Outcome::Stopped;
    }
    command_actuators();
    return Outcome::Running;
  }
}

void McuBridge::shut_down(std::size_t index, std::int64_t time_ns, McuListener& listener) {
  process_.reset();
  listener.on_stop(index, time_ns);
}

void McuBridge::release_actuators() {
  for (const auto& m : desc_.motors)
    vehicle_.command_motor(static_cast<std::size_t>(vehicle_.motor_index(m.motor)), {0, MotorDirection::Coast});
  for (const auto& s : desc_.servos) vehicle_.command_servo(static_cast<std::size_t>(vehicle_.servo_index(s.servo)), 0);
}

}  // namespace sear
