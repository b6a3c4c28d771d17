// What a run shows, as it happens, to whoever watches it from outside the simulation (the LCM
// bridge, a viewer, the CAN logs). A tap only watches: nothing it does changes what the run computes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "devices/serial_byte.h"
#include "lockstep_link.h"

namespace sear {

class Simulation;
struct CanTransfer;  // runtime/can_bus.hpp

class RunTap {
 public:
  virtual ~RunTap() = default;
  // A firmware's pin, PWM, servo, UART or CAN events, in its time order, a drain's worth at a time
  // (as McuListener::on_events); `mcu` as Lockstep::mcu(i).
  virtual void on_mcu_events(std::size_t /*mcu*/, const sear_event* /*events*/, std::size_t /*count*/) {}
  // What device `device` (index into that MCU's McuDesc::devices) measured for its model in the
  // firmware's process, for the coming quantum.
  virtual void on_sample(std::size_t /*mcu*/, std::size_t /*device*/, const sear_link_sample& /*sample*/) {}
  // What device `device`'s model in the firmware's process gave the firmware, latest at `time_ns`
  // (volts, a level, an echo's width, a count, register values in SI): `values` as
  // tools/lcm/reading_meaning.hpp names them per element. Told after each quantum in which it changed.
  virtual void on_reading(std::size_t /*mcu*/, std::size_t /*device*/, std::int64_t /*time_ns*/,
                          const double* /*values*/, std::size_t /*count*/) {}
  // An MCU whose engine counts the chip's cycles (the AVR engine): its cycles so far and how many
  // were busy, told after each of its quanta.
  virtual void on_chip_cycles(std::size_t /*mcu*/, std::uint64_t /*cycles*/, std::uint64_t /*busy*/) {}
  // Bytes a UART device put on its wire (`from_device`) or that reached it, in time order.
  virtual void on_wire_bytes(std::size_t /*mcu*/, std::size_t /*device*/, bool /*from_device*/,
                             const serial_byte* /*bytes*/, std::size_t /*count*/) {}
  // A frame that went over CAN bus `bus` (index into ProjectDesc::can_buses).
  virtual void on_can_frame(std::size_t /*bus*/, const CanTransfer& /*transfer*/) {}
  // The world after each step, once every MCU finished its quantum.
  virtual void on_step(const Simulation& /*sim*/) {}
};

}  // namespace sear

namespace sear {

// Several taps as one, told in the order they were added.
class RunTaps final : public RunTap {
 public:
  void add(RunTap* tap) { taps_.push_back(tap); }
  bool empty() const { return taps_.empty(); }
  void on_mcu_events(std::size_t mcu, const sear_event* events, std::size_t count) override {
    for (RunTap* t : taps_) t->on_mcu_events(mcu, events, count);
  }
  void on_sample(std::size_t mcu, std::size_t device, const sear_link_sample& s) override {
    for (RunTap* t : taps_) t->on_sample(mcu, device, s);
  }
  void on_reading(std::size_t mcu, std::size_t device, std::int64_t time_ns, const double* values,
                  std::size_t count) override {
    for (RunTap* t : taps_) t->on_reading(mcu, device, time_ns, values, count);
  }
  void on_chip_cycles(std::size_t mcu, std::uint64_t cycles, std::uint64_t busy) override {
    for (RunTap* t : taps_) t->on_chip_cycles(mcu, cycles, busy);
  }
  void on_wire_bytes(std::size_t mcu, std::size_t device, bool from_device, const serial_byte* bytes,
                     std::size_t count) override {
    for (RunTap* t : taps_) t->on_wire_bytes(mcu, device, from_device, bytes, count);
  }
  void on_can_frame(std::size_t bus, const CanTransfer& transfer) override {
    for (RunTap* t : taps_) t->on_can_frame(bus, transfer);
  }
  void on_step(const Simulation& sim) override {
    for (RunTap* t : taps_) t->on_step(sim);
  }

 private:
  std::vector<RunTap*> taps_;
};

}  // namespace sear
