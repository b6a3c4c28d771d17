#include "runtime/mcu_bridge.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "scene/device_kind.hpp"

namespace sear {
namespace {

constexpr std::int64_t kStdoutCheckNs = 10'000'000;

std::int64_t call_cost_ns(const McuDesc& d) { return std::llround(d.hal_call_cycles * 1e9 / d.clock_hz); }

std::vector<int> servo_pins(const McuDesc& d) {
  std::vector<int> pins;
  for (const auto& s : d.servos) pins.push_back(s.pin);
  return pins;
}

}  // namespace

McuBridge::McuBridge(const McuDesc& desc, const WorldDesc& world, std::string id, std::size_t index, Vehicle& vehicle,
                     std::uint64_t seed, const std::string& host_log, const McuRunOptions& options)
    : desc_(desc), id_(std::move(id)), index_(index), tap_(options.tap), vehicle_(vehicle), servo_wires_(servo_pins(desc)) {
  DeviceHost host(desc_, world, seed, inputs_);
  for (std::size_t i = 0; i < desc_.devices.size(); ++i) {
    host.set_device(i);
    devices_.push_back(desc_.devices[i].kind->make(desc_.devices[i], host));
    soft_input_.push_back(devices_.back()->uart() ? add_soft_uart_input(desc_.devices[i], *devices_.back()->uart(), host) : -1);
    input_device_.resize(inputs_.size(), i);
  }
  pin_listener_.fill(-1);
  soft_tx_link_.fill(-1);
  for (std::size_t i = 0; i < devices_.size(); ++i) {
    const DeviceDesc& d = desc_.devices[i];
    for (std::size_t w = 0; w < d.wires.size(); ++w) {
      if (d.wires[w] < 0 && soft_input_[i] < 0) continue;
      if (d.kind->wires[w].kind == WireKind::McuPin) pin_listener_[static_cast<std::size_t>(d.wires[w])] = static_cast<int>(i);
      if (d.kind->wires[w].kind == WireKind::UartPort && devices_[i]->uart()) {
        UartDevice* device = devices_[i]->uart();
        const auto host_end = options.host_serial.find(id_ + "." + d.name);
        HostSerialEnd* host_side = host_end == options.host_serial.end() ? nullptr : host_end->second;
        // A host's serial port reads RS-232 polarity as it should: the inversion a MaxBotix's
        // TX needs before an MCU's UART is not there on a PC's side.
        serial_.push_back({device, i, static_cast<std::uint8_t>(d.wires[w]), host_side, SerialWire(false),
                           SerialWire(!host_side && device->inverted()), device->baud(), 0});
        serial_.back().to_device.set_receiver_baud(device->baud(), 0);
        serial_.back().to_mcu.set_sender_baud(device->baud(), 0);  // a device sends at the rate it listens at
        if (soft_input_[i] >= 0) {  // on a soft UART's pins: no port, its frames played out as edges
          serial_.back().port = SEAR_LINK_UARTS;
          serial_.back().soft_input = soft_input_[i];
          soft_tx_link_[static_cast<std::size_t>(d.soft_tx_pin)] = static_cast<int>(serial_.size() - 1);
        }
      }
    }
  }
  if (inputs_.size() > SEAR_LINK_MAX_INPUTS)  // the loader already said where
    throw std::runtime_error(fmt::format("mcu {}: more than {} inputs", id_, SEAR_LINK_MAX_INPUTS));
  receive_next_.assign(desc_.uarts.size(), 0);
  // More than any device sends in a quantum at 2 Mbaud; sized once, as it is asked for every quantum.
  if (!serial_.empty()) sent_bytes_.resize(4096);
  McuProcessOptions process;
  process.hang_timeout_s = options.hang_timeout_s;
  process.call_cost_ns = call_cost_ns(desc_);
  process.max_file_bytes = options.max_file_bytes;
  process.args = desc_.firmware_args;
  process.eeprom_file = desc_.eeprom_file;
  if (desc_.engine == "avr") process.pass_env = {"SEAR_AVR_SINGLE_STEP"};  // engines/avr/straight_runs.h
  process_ = std::make_unique<McuProcess>(desc_.firmware_executable, host_log, process, &McuBridge::setup_link, this);
}

int McuBridge::add_soft_uart_input(const DeviceDesc& d, const UartDevice& device, DeviceHost& host) {
  if (d.soft_rx_pin < 0) return -1;
  sear_link_input in = blank_input(SEAR_INPUT_UART_PINS);
  in.pins[0] = static_cast<std::uint32_t>(d.soft_rx_pin);
  in.pins[1] = static_cast<std::uint32_t>(d.soft_tx_pin);
  in.param[0] = device.inverted() ? 1 : 0;
  return static_cast<int>(host.add_input(in));
}

void McuBridge::soft_tx_edge(const sear_event& e) {
  SerialLink& s = serial_[static_cast<std::size_t>(soft_tx_link_[e.index])];
  line_bytes_.clear();
  s.from_pin.set_baud(s.device_baud);
  s.from_pin.edge(static_cast<int>(e.value), e.time_ns, line_bytes_);
  for (const serial_byte& b : line_bytes_) s.to_device.send(b);
}

void McuBridge::setup_link(sear_link& link, const void* context) {
  const auto& self = *static_cast<const McuBridge*>(context);
  const McuDesc& d = self.desc_;
  link.hal_call_cost_ns = call_cost_ns(d);
  link.avcc_v = d.avcc_v;
  link.aref_v = d.aref_v;
  std::copy(self.inputs_.begin(), self.inputs_.end(), link.inputs);
  link.input_count = static_cast<std::uint32_t>(self.inputs_.size());
  for (const auto& u : d.uarts)
    if (u.loopback) link.uart_loopback_mask |= 1u << u.port;
}

void McuBridge::begin_quantum(const PhysicsWorld& physics, std::int64_t t0, std::int64_t t1) {
  if (!process_ || process_->failure()) return;
  sear_link& link = process_->link();
  // Samples and counts are put together here and copied into the link once, last: a firmware (or
  // anything it forked) can write the link at any time, so nothing the simulator sorts or
  // indexes with is read back from it.
  samples_.clear();
  std::uint32_t rx_count = 0;
  const SenseContext context{physics, vehicle_, vehicle_.chassis_body(), vehicle_.entity(), t0, t1};
  for (const auto& device : devices_) device->sample(context, samples_);
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
  rx_count = exchange_serial(t0, t1, link, rx_count);
  const std::vector<sear_link_sample>& samples = samples_.sorted();
  std::copy(samples.begin(), samples.end(), link.samples);
  if (tap_)
    for (const sear_link_sample& sample : samples) tap_->on_sample(index_, input_device_[sample.input], sample);
  link.sample_count = static_cast<std::uint32_t>(samples.size());
  link.rx_count = rx_count;
  // What the bus did for the controller up to t1. A quantum carries at most SEAR_LINK_MAX_CAN (the
  // shortest frames back to back at 1 Mbit/s over the longest step); any more would wait here.
  std::uint32_t can_count = 0;
  while (!can_records_.empty() && can_records_.front().time_ns < t1 && can_count < SEAR_LINK_MAX_CAN) {
    link.can[can_count++] = can_records_.front();
    can_records_.pop_front();
  }
  link.can_count = can_count;
  process_->start_quantum(t1);
}

void McuBridge::note_device_baud(SerialLink& s, std::int64_t now_ns) {
  if (s.device->baud() == s.device_baud) return;
  s.device_baud = s.device->baud();
  // A device that cannot say when learnt it now; changes go to the line in time order.
  s.baud_since_ns = std::max(s.baud_since_ns, s.device->baud_since_ns() > 0 ? s.device->baud_since_ns() : now_ns);
  s.to_device.set_receiver_baud(s.device_baud, s.baud_since_ns);
  s.to_mcu.set_sender_baud(s.device_baud, s.baud_since_ns);
}

void McuBridge::take_from_host(SerialLink& s, std::int64_t t0, std::int64_t t1) {
  const std::uint32_t baud = s.host->baud();
  if (baud != s.host_baud) {
    s.host_baud = baud;
    s.to_mcu.set_receiver_baud(baud, t0);
  }
  if (!baud) return;  // a host end with no rate set sends nothing
  // Only the bytes that start on the line before t1: the rest waits in the pty, whose writer then
  // blocks as on a real port, instead of piling up here ever further ahead of the clock.
  const std::int64_t frame = serial_frame_ns(baud);
  std::int64_t end = std::max(s.host_sent_end_ns, t0);
  std::uint8_t bytes[256];
  const std::size_t room = static_cast<std::size_t>(std::max<std::int64_t>(0, (t1 - end + frame - 1) / frame));
  const std::size_t n = room ? s.host->read(bytes, std::min(room, sizeof bytes)) : 0;
  for (std::size_t i = 0; i < n; ++i) {
    end += frame;
    s.to_device.send({end, baud, bytes[i], {}});
  }
  s.host_sent_end_ns = end;
}

std::uint32_t McuBridge::exchange_serial(std::int64_t t0, std::int64_t t1, sear_link& link, std::uint32_t rx_count) {
  for (SerialLink& s : serial_) {
    if (s.host) take_from_host(s, t0, t1);
    // What the firmware (or the host) sent up to t0 reaches the device, at the rate it listens at.
    note_device_baud(s, t0);
    line_bytes_.clear();
    if (s.soft_input >= 0) {  // the firmware's TX pin held its level up to t0
      s.from_pin.set_baud(s.device_baud);
      s.from_pin.known_until(t0, line_bytes_);
      for (const serial_byte& b : line_bytes_) s.to_device.send(b);
      line_bytes_.clear();
    }
    s.to_device.receive_until(t0, line_bytes_);
    for (const serial_byte& b : line_bytes_) s.device->receive(b);
    if (tap_ && !line_bytes_.empty()) tap_->on_wire_bytes(index_, s.device_index, false, line_bytes_.data(), line_bytes_.size());
    if (s.soft_input >= 0 && !s.host) {
      soft_uart_out(s, t0, t1);
      continue;
    }
    // Its answers, no earlier than t0: the firmware's clock is there already.
    const std::size_t n = s.device->transmit(t0, t1, sent_bytes_.data(), sent_bytes_.size());
    for (std::size_t i = 0; i < n; ++i) s.to_mcu.send(sent_bytes_[i]);
    if (tap_ && n) tap_->on_wire_bytes(index_, s.device_index, true, sent_bytes_.data(), n);
    note_device_baud(s, t0);  // a reply sent just now may have switched it
    line_bytes_.clear();
    s.to_mcu.receive_until(t1, line_bytes_);
    if (s.host) {
      s.host->write(line_bytes_.data(), line_bytes_.size());
      continue;
    }
    for (const serial_byte& b : line_bytes_) {
      if (rx_count == SEAR_LINK_MAX_RX) break;
      sear_link_rx& rx = link.rx[rx_count++];
      rx = {};
      rx.time_ns = b.end_ns;
      rx.port = s.port;
      rx.byte = b.value;
    }
  }
  return rx_count;
}

// A device on a soft UART's pins: each byte it sends is a sample at its start edge, from which the
// firmware's process plays the frame out on the RX pin. So that no start edge falls before a
// quantum already run, the bytes asked for are those that start before t1 (end within a frame).
void McuBridge::soft_uart_out(SerialLink& s, std::int64_t t0, std::int64_t t1) {
  const std::int64_t frame = serial_frame_ns(s.device_baud);
  const std::size_t n = s.device->transmit(t0, t1 + frame, sent_bytes_.data(), sent_bytes_.size());
  for (std::size_t i = 0; i < n; ++i) {
    const serial_byte& b = sent_bytes_[i];
    samples_.add(b.end_ns - serial_frame_ns(b.baud), s.soft_bytes++, static_cast<std::uint32_t>(s.soft_input),
                 {static_cast<double>(b.value), static_cast<double>(b.baud)});
  }
  if (tap_ && n) tap_->on_wire_bytes(index_, s.device_index, true, sent_bytes_.data(), n);
  note_device_baud(s, t0);
}

void McuBridge::drain(std::size_t index, McuListener& listener) {
  // Each event has passed the link's checks: a firmware that scribbled over its queue is stopped
  // at the first bad one, and nothing it made up reaches the pins, the motors or a file.
  const std::vector<sear_event>& events = process_->events();
  for (const sear_event& e : events) {
    switch (e.kind) {
      case SEAR_EVENT_PIN_MODE:
        pin_output_[e.index] = e.value == 1;  // OUTPUT
        usage_.made_output[e.index] = usage_.made_output[e.index] || pin_output_[e.index];
        // An output's level follows as a PIN event; an input lets go of the device's line.
        if (!pin_output_[e.index] && pin_listener_[e.index] >= 0)
          devices_[static_cast<std::size_t>(pin_listener_[e.index])]->pin_written(e.index, -1, e.time_ns);
        break;
      case SEAR_EVENT_PIN:
        if (soft_tx_link_[e.index] >= 0) soft_tx_edge(e);
        pin_drive_[e.index] = e.value ? 255 : 0;
        usage_.levels[e.index] |= e.value ? 2 : 1;
        if (servo_wires_.level(e.index, e.value != 0, e.time_ns)) usage_.waveform[e.index] = true;
        if (pin_listener_[e.index] >= 0)
          devices_[static_cast<std::size_t>(pin_listener_[e.index])]->pin_written(e.index, e.value ? 1 : 0, e.time_ns);
        break;
      case SEAR_EVENT_PWM:
        pin_drive_[e.index] = static_cast<int>(e.value);
        usage_.waveform[e.index] = true;
        break;
      case SEAR_EVENT_SERVO:
        servo_wires_.announced(e.index, static_cast<int>(e.value));
        usage_.waveform[e.index] = usage_.waveform[e.index] || e.value;
        break;
      case SEAR_EVENT_UART_BEGIN:
        port_baud_[e.index] = e.value;
        usage_.uart_begun[e.index] = true;
        for (SerialLink& s : serial_)
          if (s.port == e.index && !s.host) s.to_mcu.set_receiver_baud(e.value, e.time_ns);
        break;
      case SEAR_EVENT_UART_TX:
        for (SerialLink& s : serial_)
          if (s.port == e.index && !s.host)
            s.to_device.send({e.time_ns, port_baud_[e.index], static_cast<std::uint8_t>(e.value), {}});
        break;
      case SEAR_EVENT_CAN_BEGIN:
        can_bitrate_ = e.value;
        ++can_begins_;
        can_requests_.clear();  // a reset controller forgets what it had queued
        break;
      case SEAR_EVENT_CAN_TX:  // the link check holds that both data events follow
        can_building_ = {e.time_ns, {}};
        can_building_.frame.id = e.value;
        can_building_.frame.dlc = e.index & 15u;
        can_building_.frame.extended = (e.index >> 4) & SEAR_CAN_EXTENDED;
        can_building_.frame.remote = (e.index >> 4) & SEAR_CAN_REMOTE;
        break;
      case SEAR_EVENT_CAN_DATA:
        for (int b = 0; b < 4; ++b)
          can_building_.frame.data[static_cast<std::size_t>(e.index * 4 + b)] = static_cast<std::uint8_t>(e.value >> (8 * b));
        if (e.index == 1) can_requests_.push_back(can_building_);
        break;
      default:
        break;
    }
  }
  // They only hear of the events, so hearing of them all once they are applied changes nothing.
  if (events.empty()) return;
  listener.on_events(index, events.data(), events.size());
  if (tap_) tap_->on_mcu_events(index, events.data(), events.size());
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
    vehicle_.command_servo(static_cast<std::size_t>(vehicle_.servo_index(s.servo)),
                           servo_wires_.pulse_us(static_cast<std::size_t>(s.pin), process_->clock_ns()));
}

void McuBridge::note_usage() {
  usage_.link = process_->link().usage;
  // Only the firmware's own process writes its stdout; the AVR engine's is simavr's. Looking is a
  // system call, a fifth of a microsecond here, that a 1 ms turn need not pay: after the first
  // turn, then once every 10 ms of sim time, which keeps the told time a sim time (runs stay
  // byte-identical).
  const std::int64_t now = process_->clock_ns();
  if (now < stdout_check_ns_ || usage_.stdout_ns || desc_.engine != "native") return;
  stdout_check_ns_ = (now / kStdoutCheckNs + 1) * kStdoutCheckNs;
  if (process_->wrote_stdout()) usage_.stdout_ns = now;
}

bool McuBridge::device_on_host(std::size_t i) const {
  return std::any_of(serial_.begin(), serial_.end(), [&](const SerialLink& s) { return s.device_index == i && s.host; });
}

bool McuBridge::take_readings() {
  sear_link& link = process_->link();
  for (std::size_t i = 0; i < inputs_.size(); ++i) {
    sear_link_reading r;
    char why[256];
    const int got = sear_link_check_reading(&link, static_cast<std::uint32_t>(i), inputs_[i].kind, process_->clock_ns(),
                                            &reading_watch_, &r, why, sizeof why);
    if (got < 0) {
      // As McuProcess stops a firmware whose events do not check out: killed, its report naming
      // the field, nothing it made up passed on.
      reading_failure_ = McuFailure{McuFailure::Kind::Corrupted, 0, why, process_->clock_ns(), process_->last_call_name()};
      process_.reset();
      return false;
    }
    if (got > 0 && tap_)
      tap_->on_reading(index_, input_device_[i], r.time_ns, r.value, sear_link_reading_values(inputs_[i].kind));
  }
  if (tap_ && link.chip_cycles) tap_->on_chip_cycles(index_, link.chip_cycles, link.chip_busy_cycles);
  return true;
}

McuBridge::Outcome McuBridge::finish_quantum(std::size_t index, McuListener& listener) {
  for (;;) {
    const McuProcess::Turn turn = process_->wait();
    if (turn == McuProcess::Turn::Interrupted) return Outcome::Interrupted;
    if (!halt_) halt_ = process_->halt();
    drain(index, listener);  // whatever it wrote before stopping is kept too
    note_usage();
    if (!process_->failure() && !take_readings()) {
      release_actuators();
      listener.on_stop(index, reading_failure_->time_ns);
      return Outcome::Stopped;
    }
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
  if (!process_) return;  // already stopped, and reported
  process_.reset();
  listener.on_stop(index, time_ns);
}

void McuBridge::release_actuators() {
  for (const auto& m : desc_.motors)
    vehicle_.command_motor(static_cast<std::size_t>(vehicle_.motor_index(m.motor)), {0, MotorDirection::Coast});
  for (const auto& s : desc_.servos) vehicle_.command_servo(static_cast<std::size_t>(vehicle_.servo_index(s.servo)), 0);
}

}  // namespace sear
