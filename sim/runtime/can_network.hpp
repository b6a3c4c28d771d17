// The project's CAN buses in lockstep: each MCU's controller is a node on its bus, as are the
// host's end (a SocketCAN interface) and SEAR's own broadcast. Frames the firmware queued in a
// quantum enter the bus at their times; the bus is then decided up to the quantum's end, and
// what it carried reaches the controllers exactly one quantum after the frame's end.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "runtime/can_bus.hpp"
#include "runtime/can_state_broadcast.hpp"
#include "runtime/host_can.hpp"
#include "runtime/mcu_bridge.hpp"
#include "runtime/run_tap.hpp"
#include "scene/description.hpp"

namespace sear {

class Simulation;

class CanNetwork {
 public:
  // `bridges` are the run's MCUs, in Lockstep's order; they must outlive the network.
  CanNetwork(const ProjectDesc& project, const std::vector<std::unique_ptr<McuBridge>>& bridges, RunTap* tap);
  ~CanNetwork();

  // Bridges bus `bus` (by name) to the host both ways. Throws std::invalid_argument naming the
  // buses there are when there is no such bus.
  void attach_host(const std::string& bus, HostCanEnd* end);

  // Before the MCUs' quanta [t0, t1): the host's frames enter at t0, SEAR's broadcasts at theirs.
  void begin_quantum(const Simulation& sim, std::int64_t t0, std::int64_t t1);
  // After them: the MCUs' frames, then the buses decided up to t1.
  void finish_quantum(std::int64_t t0, std::int64_t t1);

 private:
  struct Bus {
    const CanBusDesc* desc;
    std::unique_ptr<CanBus> bus;
    std::vector<std::size_t> node_mcu;  // per node: the bridge, or kNotMcu
    HostCanEnd* host = nullptr;
    std::size_t host_node = 0;
    std::unique_ptr<CanStateBroadcast> broadcast;
  };
  static constexpr std::size_t kNotMcu = SIZE_MAX;
  // Host frames waiting for the bus before the host's socket is left unread: two seconds of a
  // full 1 Mbit/s bus.
  static constexpr std::size_t kHostBacklog = 16384;
  // A host end that failed (its interface went down, its queue stayed full) is said once and
  // let go; the run goes on.
  void host_failed(Bus& b, const std::string& why);

  const std::vector<std::unique_ptr<McuBridge>>& bridges_;
  RunTap* tap_;
  std::vector<Bus> buses_;
  std::vector<std::size_t> bus_of_;   // per bridge: its bus, or kNotMcu
  std::vector<std::size_t> node_of_;  // per bridge: its node on that bus
  std::vector<bool> warned_rate_;     // per bridge: its firmware began at another rate, said once
  std::vector<std::uint32_t> begins_seen_;  // per bridge: its can_begin() calls the bus has acted on
  std::vector<CanFrame> host_frames_;  // scratch
  std::vector<CanTransfer> done_;      // scratch
  std::vector<RobotBroadcastState> robot_states_;  // scratch
};

}  // namespace sear
