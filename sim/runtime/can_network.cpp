#include "runtime/can_network.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "runtime/can_state_broadcast.hpp"
#include "runtime/simulation.hpp"

namespace sear {
namespace {

// Reaches the controller one quantum after the frame's end: the bus is decided at quantum ends, and
// a fixed delay keeps the frames' spacing, so a firmware takes each in turn (its receive interrupt
// runs between them) as it would on the wire.
sear_link_can record_of(const CanTransfer& t, sear_can_record kind, const CanCounters& counters, std::int64_t delay_ns) {
  sear_link_can r{};
  r.time_ns = t.end_ns + delay_ns;
  r.id = t.frame.id;
  r.record = static_cast<std::uint8_t>(kind);
  r.flags = static_cast<std::uint8_t>((t.frame.extended ? SEAR_CAN_EXTENDED : 0u) | (t.frame.remote ? SEAR_CAN_REMOTE : 0u));
  r.dlc = t.frame.dlc;
  r.tec = static_cast<std::uint8_t>(std::min<int>(counters.tec, 255));
  r.rec = static_cast<std::uint8_t>(std::min<int>(counters.rec, 255));
  for (std::size_t i = 0; i < 8; ++i) r.data[i] = t.frame.data[i];
  return r;
}

}  // namespace

CanNetwork::CanNetwork(const ProjectDesc& project, const std::vector<std::unique_ptr<McuBridge>>& bridges, RunTap* tap)
    : bridges_(bridges), tap_(tap), bus_of_(bridges.size(), kNotMcu), node_of_(bridges.size(), 0),
      warned_rate_(bridges.size(), false), begins_seen_(bridges.size(), 0) {
  for (const CanBusDesc& desc : project.can_buses) {
    Bus b;
    b.desc = &desc;
    b.bus = std::make_unique<CanBus>(desc.bitrate);
    if (desc.broadcast_hz > 0) {
      b.broadcast = std::make_unique<CanStateBroadcast>(*b.bus, desc.broadcast_hz);
      b.node_mcu.push_back(kNotMcu);
    }
    buses_.push_back(std::move(b));
  }
  for (std::size_t m = 0; m < bridges_.size(); ++m) {
    const std::string& name = bridges_[m]->desc().can_bus;
    if (name.empty()) continue;
    for (std::size_t b = 0; b < buses_.size(); ++b) {
      if (buses_[b].desc->name != name) continue;
      bus_of_[m] = b;
      node_of_[m] = buses_[b].bus->add_node(bridges_[m]->id());
      buses_[b].node_mcu.push_back(m);
    }
  }
}

CanNetwork::~CanNetwork() = default;

void CanNetwork::attach_host(const std::string& bus, HostCanEnd* end) {
  std::vector<std::string> names;
  for (Bus& b : buses_) {
    names.push_back(b.desc->name);
    if (b.desc->name != bus) continue;
    if (b.host) throw std::invalid_argument(fmt::format("CAN bus '{}' is bridged to the host twice", bus));
    b.host = end;
    b.host_node = b.bus->add_node("host");
    b.node_mcu.push_back(kNotMcu);
    // The host's controller acknowledges what it receives, as a real interface on the bus does.
    b.bus->set_listening(b.host_node, true);
    return;
  }
  throw std::invalid_argument(
      fmt::format("no CAN bus '{}' in the project (it has: {})", bus, fmt::join(names, ", ")));
}

void CanNetwork::begin_quantum(const Simulation& sim, std::int64_t t0, std::int64_t t1) {
  for (Bus& b : buses_) {
    // A host sending faster than the bus carries is left to wait in its own socket (whose
    // kernel queue then drops, as a real interface's does) rather than in an endless queue here.
    if (b.host && b.bus->pending(b.host_node) < kHostBacklog) {
      host_frames_.clear();
      try {
        b.host->read_available(host_frames_);
      } catch (const std::exception& e) {
        host_failed(b, e.what());
      }
      for (const CanFrame& f : host_frames_) b.bus->request(b.host_node, t0, f, 0);
    }
    if (b.broadcast && b.broadcast->next_due_ns() < t1) {
      // The state as the world is at t0, for every broadcast falling due in this quantum.
      robot_states_.clear();
      for (std::size_t r = 0; r < sim.robot_count(); ++r) {
        const VehicleState s = sim.robot_state(r);
        RobotBroadcastState out;
        for (int k = 0; k < 3; ++k) {
          out.position_m[static_cast<std::size_t>(k)] = s.position_m[k];
          out.roll_pitch_yaw_rad[static_cast<std::size_t>(k)] = s.roll_pitch_yaw[k];
          out.angular_velocity_rps[static_cast<std::size_t>(k)] = s.angular_velocity[k];
        }
        out.forward_speed_mps = s.forward_speed_mps;
        robot_states_.push_back(out);
      }
      while (b.broadcast->next_due_ns() < t1) b.broadcast->publish(std::max(b.broadcast->next_due_ns(), t0), robot_states_);
    }
  }
}

void CanNetwork::host_failed(Bus& b, const std::string& why) {
  fmt::print(stderr, "sear: --can {}: {}; the bus goes on without the host\n", b.desc->name, why);
  b.bus->set_listening(b.host_node, false);
  b.bus->clear(b.host_node);
  b.host = nullptr;
}

void CanNetwork::finish_quantum(std::int64_t t0, std::int64_t t1) {
  for (std::size_t m = 0; m < bridges_.size(); ++m) {
    if (bus_of_[m] == kNotMcu) continue;
    Bus& b = buses_[bus_of_[m]];
    const std::uint32_t rate = bridges_[m]->can_bitrate();
    const bool running = bridges_[m]->running();
    // A controller begun (again) drops what it had queued, as the MCP2515's reset does; it
    // answers on the bus for the whole quantum it began in, a quantum's approximation of the
    // instant it did.
    if (bridges_[m]->can_begins() != begins_seen_[m] || !running) b.bus->clear(node_of_[m]);
    begins_seen_[m] = bridges_[m]->can_begins();
    b.bus->set_listening(node_of_[m], running && rate == b.desc->bitrate);
    const std::vector<CanRequest> requests = bridges_[m]->take_can_requests();
    if (rate != b.desc->bitrate) {
      // A controller at another rate only ever sees error frames on a real bus: none of its
      // frames gets through. Said once, as the firmware cannot tell.
      if ((rate || !requests.empty()) && !warned_rate_[m]) {
        warned_rate_[m] = true;
        fmt::print(stderr, "sear: mcu {} began CAN at {} bit/s on bus '{}', which runs at {} bit/s: its frames never get through\n",
                   bridges_[m]->id(), rate, b.desc->name, b.desc->bitrate);
      }
      continue;
    }
    for (const CanRequest& r : requests) b.bus->request(node_of_[m], r.time_ns, r.frame, m);
  }
  for (std::size_t bi = 0; bi < buses_.size(); ++bi) {
    Bus& b = buses_[bi];
    done_.clear();
    b.bus->run_until(t1, done_);
    for (const CanTransfer& t : done_) {
      if (tap_) tap_->on_can_frame(bi, t);
      if (b.host && t.acked && t.node != b.host_node) {
        try {
          b.host->write(t.frame);
        } catch (const std::exception& e) {
          host_failed(b, e.what());
        }
      }
      for (std::size_t node = 0; node < b.node_mcu.size(); ++node) {
        const std::size_t m = b.node_mcu[node];
        if (m == kNotMcu || !bridges_[m]->running()) continue;
        if (node == t.node)
          bridges_[m]->deliver_can(
              record_of(t, t.acked ? SEAR_CAN_SENT : SEAR_CAN_NO_ACK, b.bus->counters(node), t1 - t0));
        else if (t.acked && bridges_[m]->can_bitrate() == b.desc->bitrate)
          bridges_[m]->deliver_can(record_of(t, SEAR_CAN_RECEIVED, b.bus->counters(node), t1 - t0));
      }
    }
  }
}

}  // namespace sear
