#include "view/mcu_panel.hpp"

#include "lcm/reading_meaning.hpp"
#include "scene/device_kind.hpp"
#include "view/frame_round.hpp"

namespace sear {
namespace {

using Json = nlohmann::ordered_json;

UartStream::Format format_of(const std::string& element) {
  if (element == "ublox_neo6m" || element == "mtk3339") return UartStream::Format::Nmea;
  if (element == "lms2xx") return UartStream::Format::Lms;
  return UartStream::Format::Raw;
}

bool on_uart(const DeviceDesc& d) {
  if (!d.kind) return false;
  for (std::size_t i = 0; i < d.kind->wires.size() && i < d.wires.size(); ++i)
    if (d.kind->wires[i].kind == WireKind::UartPort && d.wires[i] >= 0) return true;
  return false;
}

Json number_or_null(double v) { return std::isfinite(v) ? Json(round_sig(v)) : Json(); }

}  // namespace

McuPanel::McuPanel(const McuDesc& desc, std::string id, int index)
    : id_(std::move(id)),
      index_(index),
      console_uart_(desc.console_uart),
      can_bus_(desc.can_bus),
      clock_hz_(desc.clock_hz) {
  for (const DeviceDesc& d : desc.devices) {
    PanelDevice p;
    p.name = d.name;
    p.element = d.kind ? d.kind->element : "";
    p.view = sensor_view(d);
    p.truth_count = std::min<std::size_t>(reading_meaning(p.element).quantity.size(), SEAR_LINK_SAMPLE_VALUES);
    if (on_uart(d)) {
      p.to_device = std::make_unique<UartStream>(format_of(p.element));
      p.from_device = std::make_unique<UartStream>(format_of(p.element));
    }
    devices_.push_back(std::move(p));
  }
  console_.reserve(kMaxConsoleLine);
}

void McuPanel::reset() {
  window_cycles_ = window_busy_ = 0;
  cpu_load_ = -1;
  pins_.clear();
  pwm_.clear();
  servo_.clear();
  console_.clear();
  stopped_.clear();
  for (PanelDevice& d : devices_) {
    d.has_truth = false;
    d.reading.clear();
    if (d.to_device) d.to_device->reset();
    if (d.from_device) d.from_device->reset();
  }
}

void McuPanel::set_watching(bool watching) {
  if (watching && !watching_) {
    for (PanelDevice& d : devices_) {
      if (d.to_device) d.to_device->resync();
      if (d.from_device) d.from_device->resync();
    }
  }
  watching_ = watching;
}

void McuPanel::on_event(const sear_event& e, LogRing& log) {
  switch (e.kind) {
    case SEAR_EVENT_PIN_MODE:
      if (e.value != 1) {  // an input drives nothing
        pins_.erase(e.index);
        pwm_.erase(e.index);
      }
      break;
    case SEAR_EVENT_PIN:
      pins_[e.index] = e.value ? 1 : 0;
      pwm_.erase(e.index);
      break;
    case SEAR_EVENT_PWM:
      pwm_[e.index] = static_cast<int>(e.value);
      pins_.erase(e.index);
      break;
    case SEAR_EVENT_SERVO:
      if (e.value) servo_[e.index] = static_cast<int>(e.value);
      else servo_.erase(e.index);
      break;
    case SEAR_EVENT_UART_TX: {
      // Console lines are logged whether or not a page watches (a few a second cost nothing), so
      // that a page opened after the run started gets what was said before it.
      if (static_cast<int>(e.index) != console_uart_) break;
      const char c = static_cast<char>(e.value);
      if (c != '\n' && c != '\r') append_printable(console_, static_cast<unsigned char>(c));
      if (c == '\n' || console_.size() >= kMaxConsoleLine) {
        LogEntry& entry = log.add();
        entry.t_ns = e.time_ns;
        entry.kind = LogEntry::Kind::Console;
        entry.mcu = index_;
        entry.text = console_;
        console_.clear();
      }
      break;
    }
    default:
      break;
  }
}

void McuPanel::on_sample(std::size_t device, const sear_link_sample& sample) {
  if (device >= devices_.size()) return;
  PanelDevice& d = devices_[device];
  d.has_truth = true;
  for (std::size_t i = 0; i < d.truth_count; ++i) d.truth[i] = sample.value[i];
}

void McuPanel::on_reading(std::size_t device, const double* values, std::size_t count) {
  if (device >= devices_.size()) return;
  devices_[device].reading.assign(values, values + count);
}

void McuPanel::on_wire_bytes(std::size_t device, bool from_device, const serial_byte* bytes, std::size_t count,
                             LogRing& log) {
  if (!watching_ || device >= devices_.size()) return;
  UartStream* stream = from_device ? devices_[device].from_device.get() : devices_[device].to_device.get();
  if (!stream) return;
  decoded_.clear();
  stream->feed(bytes, count, decoded_);
  for (LogEntry& d : decoded_) {
    LogEntry& e = log.add();
    e.t_ns = d.t_ns;
    e.kind = d.kind;
    e.mcu = index_;
    e.device = static_cast<int>(device);
    e.from_device = from_device;
    e.crc_ok = d.crc_ok;
    e.text.swap(d.text);
    e.hex.swap(d.hex);
  }
}

// A load over whole windows of the chip's time, so that it reads the same whatever the frame rate.
void McuPanel::on_chip_cycles(std::uint64_t cycles, std::uint64_t busy) {
  const double window = 0.1 * clock_hz_;
  if (cycles < window_cycles_ || busy < window_busy_) window_cycles_ = window_busy_ = 0;  // a reset
  if (static_cast<double>(cycles - window_cycles_) < window) return;
  cpu_load_ = static_cast<double>(busy - window_busy_) / static_cast<double>(cycles - window_cycles_);
  window_cycles_ = cycles;
  window_busy_ = busy;
}

void McuPanel::put_state(Json& out) const {
  out["running"] = stopped_.empty();
  out["stopped"] = stopped_.empty() ? Json() : Json(stopped_);
  out["cpu_load"] = cpu_load_ < 0 ? Json() : Json(std::round(cpu_load_ * 1e4) / 1e4);
  Json pins = Json::object(), pwm = Json::object(), servo = Json::object();
  for (const auto& [pin, level] : pins_) pins[std::to_string(pin)] = level;
  for (const auto& [pin, duty] : pwm_) pwm[std::to_string(pin)] = duty;
  for (const auto& [pin, us] : servo_) servo[std::to_string(pin)] = us;
  out["pins"] = std::move(pins);
  out["pwm"] = std::move(pwm);
  out["servo"] = std::move(servo);
  Json readings = Json::object(), truth = Json::object();
  for (const PanelDevice& d : devices_) {
    if (!d.reading.empty()) {
      // Named as tools/lcm/reading_meaning.hpp names them; values past its list as value<i>.
      const ReadingMeaning& m = output_meaning(d.element);
      Json r = Json::object();
      for (std::size_t i = 0; i < d.reading.size(); ++i)
        r[i < m.quantity.size() ? std::string(m.quantity[i]) : "value" + std::to_string(i)] = number_or_null(d.reading[i]);
      readings[d.name] = std::move(r);
    }
    if (d.has_truth) {
      const ReadingMeaning& m = reading_meaning(d.element);
      Json t = Json::object();
      for (std::size_t i = 0; i < d.truth_count; ++i) t[m.quantity[i]] = number_or_null(d.truth[i]);
      truth[d.name] = std::move(t);
    }
  }
  out["readings"] = std::move(readings);
  out["truth"] = std::move(truth);
}

}  // namespace sear
