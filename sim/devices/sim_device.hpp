// The simulator's half of a device: it measures physical truth for the device's model and, for a
// device on a serial line, hosts that model in the simulator's process. The lockstep bridge
// drives every device through this one interface, whatever its kind (see device_kinds.cpp).
#pragma once

#include <ode/ode.h>

#include <cstdint>
#include <initializer_list>
#include <vector>

#include "lockstep_link.h"
#include "physics/physics_world.hpp"
#include "physics/vehicle.hpp"
#include "scene/description.hpp"

namespace sear {

class UartDevice;

// The world as it is at the start of the quantum [t0_ns, t1_ns), seen from the device's robot.
struct SenseContext {
  const PhysicsWorld& physics;
  const Vehicle& vehicle;
  dBodyID chassis;
  int self_entity;  // the robot's own entity: its sensors never see it
  std::int64_t t0_ns;
  std::int64_t t1_ns;
};

// Calls measure(k) for every tick k of a device's own cycle (k * period_ns) in the quantum.
template <class Measure>
void for_each_tick(std::int64_t period_ns, const SenseContext& c, Measure measure) {
  for (std::int64_t k = (c.t0_ns + period_ns - 1) / period_ns; k * period_ns < c.t1_ns; ++k) measure(k);
}

// Samples of truth for the firmware's process, collected for one quantum.
class SampleSink {
 public:
  void clear() { samples_.clear(); }
  // Dropped beyond the link's capacity (a device sampling faster than a quantum can hold).
  void add(std::int64_t time_ns, std::uint64_t index, std::uint32_t input, std::initializer_list<double> values);
  // In time order; ties keep the order they were added in.
  const std::vector<sear_link_sample>& sorted();

 private:
  std::vector<sear_link_sample> samples_;
};

// What a device's factory gets: the MCU it is wired to and the link inputs it may claim.
class DeviceHost {
 public:
  DeviceHost(const McuDesc& mcu, const WorldDesc& world, std::uint64_t run_seed, std::vector<sear_link_input>& inputs)
      : mcu_(mcu), world_(world), run_seed_(run_seed), inputs_(inputs) {}
  const McuDesc& mcu() const { return mcu_; }
  const WorldDesc& world() const { return world_; }  // its GPS origin and magnetic field
  // Claims an input of the link for the device's model in the firmware's process; its noise seed
  // is derived from the run's seed and the input's place. Returns its index.
  std::uint32_t add_input(sear_link_input input);
  // An independent seed for noise drawn in the simulator's process, per device and salt.
  std::uint64_t seed(std::uint64_t salt) const;
  void set_device(std::size_t index) { device_ = index; }

 private:
  const McuDesc& mcu_;
  const WorldDesc& world_;
  std::uint64_t run_seed_;
  std::vector<sear_link_input>& inputs_;
  std::size_t device_ = 0;  // the device being built: its place among the MCU's devices
};

// A link input with no pins wired and no figures yet.
sear_link_input blank_input(sear_input_kind kind);

// The bridge calls sample() at the start of every quantum and, for a device on a serial line, then
// exchanges its bytes within the same call: a device may keep the context for that exchange, and
// only for it. Devices are not copied (a UART device's model may point back at it).
class SimDevice {
 public:
  SimDevice() = default;
  SimDevice(const SimDevice&) = delete;
  SimDevice& operator=(const SimDevice&) = delete;
  virtual ~SimDevice() = default;
  // Measures what its model needs for [t0, t1) and adds the samples.
  virtual void sample(const SenseContext& context, SampleSink& sink) = 0;
  // The device on a serial line, when it is one (its port is its kind's UartPort wire).
  virtual UartDevice* uart() { return nullptr; }
  // The firmware drove one of the device's McuPin wires to `level` (0 or 1) at t_ns, or let go of
  // it (-1: the pin became an input).
  virtual void pin_written(int pin, int level, std::int64_t t_ns) {
    (void)pin;
    (void)level;
    (void)t_ns;
  }
};

}  // namespace sear
