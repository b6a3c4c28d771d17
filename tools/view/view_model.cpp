#include "view/view_model.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "runtime/can_bus.hpp"
#include "runtime/simulation.hpp"
#include "scene/description.hpp"
#include "view/frame_json.hpp"
#include "view/frame_round.hpp"
#include "view/mcu_panel.hpp"
#include "view/scene_json.hpp"

namespace sear {
namespace {

using Json = nlohmann::ordered_json;

const char* kind_name(LogEntry::Kind k) {
  switch (k) {
    case LogEntry::Kind::Console: return "console";
    case LogEntry::Kind::Nmea: return "nmea";
    case LogEntry::Kind::Lms: return "lms";
    case LogEntry::Kind::Bytes: return "bytes";
    case LogEntry::Kind::Can: return "can";
  }
  return "?";
}

// candump's compact form: 3 hex digits of a standard ID, 8 of an extended one, then the data,
// or R for a remote frame.
std::string can_text(const CanTransfer& t) {
  const CanFrame& f = t.frame;
  std::string s = f.extended ? fmt::format("{:08X}#", f.id) : fmt::format("{:03X}#", f.id);
  if (f.remote) s += 'R';
  else
    for (std::size_t i = 0; i < f.dlc && i < f.data.size(); ++i) s += fmt::format("{:02X}", f.data[i]);
  if (!t.acked) s += " (no ACK)";
  return s;
}

}  // namespace

struct ViewModel::State {
  explicit State(const ProjectDesc& p) : project(p), scene(sear::scene_json(project)), world(project) {
    int index = 0;
    for (const RobotDesc& r : project.robots)
      for (const McuDesc& m : r.mcus) panels.emplace_back(m, r.name + "." + m.name, index++);
  }

  Json entry_json(const LogEntry& e) const {
    Json j = {{"seq", e.seq}, {"t", round_seconds(e.t_ns)}, {"kind", kind_name(e.kind)}};
    if (e.kind == LogEntry::Kind::Can) {
      j["bus"] = e.bus >= 0 && static_cast<std::size_t>(e.bus) < project.can_buses.size()
                     ? project.can_buses[static_cast<std::size_t>(e.bus)].name
                     : std::string();
    } else if (e.device >= 0) {
      j["device"] = panels[static_cast<std::size_t>(e.mcu)].devices()[static_cast<std::size_t>(e.device)].name;
      j["dir"] = e.from_device ? "tx" : "rx";
    }
    if (!e.text.empty() || e.kind != LogEntry::Kind::Bytes) j["text"] = e.text;
    if (!e.hex.empty()) j["hex"] = e.hex;
    if (e.crc_ok >= 0) j["crc_ok"] = e.crc_ok == 1;
    return j;
  }

  // The panels an entry shows in: its MCU's, or for a CAN frame every MCU on that bus.
  template <class F>
  void for_panels_of(const LogEntry& e, F f) const {
    if (e.mcu >= 0) {
      if (static_cast<std::size_t>(e.mcu) < panels.size()) f(static_cast<std::size_t>(e.mcu));
      return;
    }
    if (e.bus < 0 || static_cast<std::size_t>(e.bus) >= project.can_buses.size()) return;
    const std::string& bus = project.can_buses[static_cast<std::size_t>(e.bus)].name;
    for (std::size_t i = 0; i < panels.size(); ++i)
      if (panels[i].can_bus() == bus) f(i);
  }

  const ProjectDesc project;
  const std::string scene;
  std::vector<McuPanel> panels;
  LogRing log;
  FrameWorld world;
  bool page_watching = true, always_watching = false;

  void update_watching() {
    for (McuPanel& p : panels) p.set_watching(page_watching || always_watching);
  }
};

ViewModel::ViewModel(const ProjectDesc& project) : s_(std::make_unique<State>(project)) {}
ViewModel::~ViewModel() = default;

const std::string& ViewModel::scene_json() const { return s_->scene; }

void ViewModel::set_watching(bool watching) {
  if (s_->page_watching == watching) return;  // cheap enough to call every step
  s_->page_watching = watching;
  s_->update_watching();
}

void ViewModel::keep_watching() {
  s_->always_watching = true;
  s_->update_watching();
}

bool ViewModel::watching() const { return s_->page_watching || s_->always_watching; }

std::uint64_t ViewModel::pending_entries(const FrameCursor& cursor) const {
  const std::uint64_t from = std::max(cursor.next_entry, s_->log.cleared_at());
  const std::uint64_t next = s_->log.next_seq();
  return next > from ? next - from : 0;
}

FrameCursor ViewModel::recent_cursor() const {
  const std::uint64_t next = s_->log.next_seq();
  const std::uint64_t held = std::max(s_->log.oldest_seq(), s_->log.cleared_at());
  return FrameCursor{next - held > kMaxEntriesPerFrame ? next - kMaxEntriesPerFrame : held};
}

std::string ViewModel::frame_json(const Simulation& sim, FrameCursor& cursor, std::size_t stream_cap,
                                  std::size_t max_entries) {
  State& s = *s_;
  Json frame = {{"type", "frame"}, {"t", round_seconds(sim.time_ns())}};
  s.world.put(sim, s.panels, frame);

  // Entries before a restart belong to the old run: skipped, not dropped. Entries the ring no
  // longer holds, and any beyond the newest `max_entries`, are dropped and counted.
  const std::uint64_t next = s.log.next_seq();
  const std::uint64_t wanted = std::max(cursor.next_entry, s.log.cleared_at());
  const std::uint64_t from = std::max(wanted, s.log.oldest_seq());
  std::uint64_t dropped = from - wanted;
  std::vector<Json> logs(s.panels.size(), Json::array());
  std::vector<std::uint64_t> panel_dropped(s.panels.size(), 0);
  const std::uint64_t shown_from = next - from > max_entries ? next - max_entries : from;
  for (std::uint64_t q = from; q < shown_from; ++q)
    s.for_panels_of(s.log.at(q), [&](std::size_t i) { ++panel_dropped[i]; });
  dropped += shown_from - from;
  // A stream (LMS telegrams, raw bytes) keeps only its newest stream_cap entries: at 35x real time
  // an LMS200 sends ~2600 telegrams a wall second, which nobody reads, and each costs the run
  // time to put in the frame. Console lines, NMEA sentences and CAN frames are kept whole.
  const auto is_stream = [](const LogEntry& e) { return e.kind == LogEntry::Kind::Lms || e.kind == LogEntry::Kind::Bytes; };
  const auto stream_of = [](const LogEntry& e) { return static_cast<std::int64_t>(e.mcu) << 32 | static_cast<std::uint32_t>(e.device); };
  std::map<std::int64_t, std::size_t> stream_skip;
  if (stream_cap != kWholeStreams) {
    for (std::uint64_t q = shown_from; q < next; ++q)
      if (is_stream(s.log.at(q))) ++stream_skip[stream_of(s.log.at(q))];
    for (auto& [stream, count] : stream_skip) count = count > stream_cap ? count - stream_cap : 0;
  }
  for (std::uint64_t q = shown_from; q < next; ++q) {
    const LogEntry& e = s.log.at(q);
    if (stream_cap != kWholeStreams && is_stream(e)) {
      std::size_t& skip = stream_skip[stream_of(e)];
      if (skip > 0) {
        --skip;
        ++dropped;
        s.for_panels_of(e, [&](std::size_t i) { ++panel_dropped[i]; });
        continue;
      }
    }
    s.for_panels_of(e, [&](std::size_t i) { logs[i].push_back(s.entry_json(e)); });
  }
  cursor.next_entry = next;

  Json mcus = Json::array();
  for (std::size_t i = 0; i < s.panels.size(); ++i) {
    Json m = {{"id", s.panels[i].id()}};
    s.panels[i].put_state(m);
    m["log"] = std::move(logs[i]);
    m["dropped"] = panel_dropped[i];
    mcus.push_back(std::move(m));
  }
  frame["mcus"] = std::move(mcus);
  frame["dropped"] = dropped;
  // Entries' text is made printable where it is built; should a byte slip through, a U+FFFD in
  // one entry beats a run ended by nlohmann's type_error.316.
  return frame.dump(-1, ' ', false, Json::error_handler_t::replace);
}

void ViewModel::restart() {
  for (McuPanel& p : s_->panels) p.reset();
  s_->log.clear();
}

void ViewModel::mcu_stopped(const std::string& mcu_id, const std::string& why) {
  for (McuPanel& p : s_->panels)
    if (p.id() == mcu_id) p.stopped(why);
}

void ViewModel::on_mcu_event(std::size_t mcu, const sear_event& event) {
  if (mcu < s_->panels.size()) s_->panels[mcu].on_event(event, s_->log);
}

void ViewModel::on_chip_cycles(std::size_t mcu, std::uint64_t cycles, std::uint64_t busy) {
  if (mcu < s_->panels.size()) s_->panels[mcu].on_chip_cycles(cycles, busy);
}

void ViewModel::on_sample(std::size_t mcu, std::size_t device, const sear_link_sample& sample) {
  if (mcu < s_->panels.size()) s_->panels[mcu].on_sample(device, sample);
}

void ViewModel::on_reading(std::size_t mcu, std::size_t device, std::int64_t, const double* values,
                           std::size_t count) {
  if (mcu < s_->panels.size()) s_->panels[mcu].on_reading(device, values, count);
}

void ViewModel::on_wire_bytes(std::size_t mcu, std::size_t device, bool from_device, const serial_byte* bytes,
                              std::size_t count) {
  if (mcu < s_->panels.size()) s_->panels[mcu].on_wire_bytes(device, from_device, bytes, count, s_->log);
}

void ViewModel::on_can_frame(std::size_t bus, const CanTransfer& transfer) {
  if (!watching()) return;
  LogEntry& e = s_->log.add();
  e.t_ns = transfer.end_ns;
  e.kind = LogEntry::Kind::Can;
  e.bus = static_cast<int>(bus);
  e.text = can_text(transfer);
}

}  // namespace sear
