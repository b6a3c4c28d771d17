// SEAR's own node on a simulated CAN bus: at a fixed rate it sends the sim clock and each robot's
// ground-truth state, in the frames tools/can/sear.dbc describes (generated from the table here).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "runtime/can_bus.hpp"
#include "runtime/can_frame.hpp"

namespace sear {

// What the broadcast says about one robot, in SI units (the lead fills it from VehicleState).
struct RobotBroadcastState {
  std::array<double, 3> position_m{};            // world frame (x east, y north, z up)
  std::array<double, 3> roll_pitch_yaw_rad{};    // Z-Y-X Euler angles of the chassis
  double forward_speed_mps = 0;                  // along the chassis x axis
  std::array<double, 3> angular_velocity_rps{};  // world frame; its z is the yaw rate
};

// One signal of a broadcast frame: little-endian (Intel) integer at start_bit, raw = round(value /
// factor) saturated to the raw range; min/max are the physical range the DBC states.
struct CanSignalDef {
  const char* name;
  int start_bit;
  int length;
  bool is_signed;
  double factor;
  double min, max;
  const char* unit;
  // The physical value in `unit`; nullptr for the clock, whose raw value is the sim time in ns.
  double (*value)(const RobotBroadcastState&);
};

struct CanMessageDef {
  const char* name;       // per-robot messages get "_R<index>" appended
  std::uint32_t base_id;  // standard ID; per-robot messages add the robot index
  bool per_robot;
  std::uint8_t dlc;
  std::vector<CanSignalDef> signals;
  const char* comment;
};

// Standard IDs 0x700-0x73F: 0x700 the clock, then 0x7T0 | robot for message type T (robots 0-15).
constexpr std::size_t kBroadcastMaxRobots = 16;
const std::vector<CanMessageDef>& broadcast_messages();

// The frames of one broadcast, in the order they are queued: the clock, then each robot's.
// Throws std::invalid_argument past kBroadcastMaxRobots robots.
std::vector<CanFrame> encode_broadcast(std::int64_t time_ns, const std::vector<RobotBroadcastState>& robots);
// The DBC text describing broadcast_messages() (tools/can/sear.dbc holds exactly this).
std::string broadcast_dbc();

class CanStateBroadcast {
 public:
  // Adds the node "sear" to `bus`. It listens (acks others' frames) like any CAN controller in
  // normal mode, so an MCU alone with it on a bus gets its frames acked.
  CanStateBroadcast(CanBus& bus, double rate_hz);

  std::size_t node() const { return node_; }
  // When the next broadcast is due: k / rate_hz seconds, k = 0, 1, ..., rounded to the ns.
  std::int64_t next_due_ns() const { return next_due_ns_; }
  // Queues one broadcast at time_ns (>= next_due_ns(), >= the bus's horizon) describing `robots`
  // then, and moves next_due_ns() past time_ns. When the previous broadcast is still queued (a
  // saturated bus, or nobody acks), this one is skipped rather than piling up.
  void publish(std::int64_t time_ns, const std::vector<RobotBroadcastState>& robots);
  std::uint64_t sent() const { return sent_; }
  std::uint64_t skipped() const { return skipped_; }

 private:
  std::int64_t due(std::int64_t k) const;

  CanBus& bus_;
  std::size_t node_;
  double rate_hz_;
  std::int64_t k_ = 0;
  std::int64_t next_due_ns_ = 0;
  std::uint64_t sent_ = 0;
  std::uint64_t skipped_ = 0;
};

}  // namespace sear
