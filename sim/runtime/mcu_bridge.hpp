// Connects one MCU's firmware to its robot: measures the wired sensors for each quantum and turns
// the firmware's pin, PWM and servo outputs into motor and servo commands.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "devices/sim_device.hpp"
#include "devices/uart_device.hpp"
#include "physics/vehicle.hpp"
#include "runtime/can_frame.hpp"
#include "runtime/host_serial.hpp"
#include "runtime/mcu_process.hpp"
#include "runtime/mcu_usage.hpp"
#include "runtime/pin_uart_decoder.hpp"
#include "runtime/run_tap.hpp"
#include "runtime/serial_wire.hpp"
#include "runtime/servo_wire.hpp"
#include "scene/description.hpp"

namespace sear {

// Receives everything a firmware did on its pins and ports, in time order per MCU.
class McuListener {
 public:
  virtual ~McuListener() = default;
  // A drain's events at once, in the order the firmware wrote them: a 500 kbaud line's bytes
  // come 50 a millisecond, and a call for each (and the taps' too) cost the reference rover
  // 1.1 k instructions a step.
  virtual void on_events(std::size_t mcu, const sear_event* events, std::size_t count) = 0;
  // The MCU stopped at its clock's time_ns: nothing it queued for later goes out after that.
  virtual void on_stop(std::size_t mcu, std::int64_t time_ns) = 0;
};

struct McuRunOptions {
  double hang_timeout_s = 5;                  // host time without progress before a firmware counts as hung
  std::uint64_t max_file_bytes = UINT64_MAX;  // the most a firmware may write to any one file
  RunTap* tap = nullptr;                      // told what the MCU and its devices do; may be null
  // UART devices taken off their MCU port and given to the host instead, by "robot.mcu.device".
  std::map<std::string, HostSerialEnd*> host_serial;
};

// A frame the firmware queued on its CAN controller, at the time of the call.
struct CanRequest {
  std::int64_t time_ns;
  CanFrame frame;
};

class McuBridge {
 public:
  // `desc.firmware_executable` must name the built firmware. `id` is "robot.mcu"; `index` is the
  // MCU's place in the run, as taps are told it.
  McuBridge(const McuDesc& desc, const WorldDesc& world, std::string id, std::size_t index, Vehicle& vehicle,
            std::uint64_t seed, const std::string& host_log, const McuRunOptions& options);

  const std::string& id() const { return id_; }
  const McuDesc& desc() const { return desc_; }

  // Measures the sensors as the world is now, at t0, and hands the firmware [t0, t1).
  void begin_quantum(const PhysicsWorld& physics, std::int64_t t0, std::int64_t t1);
  enum class Outcome { Running, Stopped, Interrupted };
  // Waits for the firmware to finish its quantum, passing its events on; then commands the
  // robot's actuators. Stopped: see failure(). Interrupted: the run was asked to stop meanwhile.
  Outcome finish_quantum(std::size_t index, McuListener& listener);
  const std::optional<McuFailure>& failure() const {
    static const std::optional<McuFailure> none;  // shut down with its robot: it did not fail
    if (reading_failure_) return reading_failure_;
    return process_ ? process_->failure() : none;
  }
  // A stopped MCU drives nothing: its motors coast and its servos get no pulses.
  void release_actuators();
  // Ends the firmware at time_ns, as its robot left the world: its process is killed and nothing
  // it queued for later is written.
  void shut_down(std::size_t index, std::int64_t time_ns, McuListener& listener);
  bool running() const { return process_ && !process_->failure(); }
  // Set once the firmware halted in an endless empty loop (it keeps running its interrupts).
  const std::optional<McuHalt>& halt() const { return halt_; }
  // What the firmware did with its pins, ports and buses so far (for the wiring report).
  const McuUsage& usage() const { return usage_; }
  // The device desc().devices[i] talks to the host rather than to the firmware's port.
  bool device_on_host(std::size_t i) const;
  // Which desc().devices entry each link input's model belongs to.
  const std::vector<std::size_t>& input_devices() const { return input_device_; }

  // CAN: the bit rate the firmware began its controller at (0: not begun), the frames it queued
  // in the quantum just finished (taken once), and what the bus did for it, passed on to the
  // firmware when the quantum its time falls in begins (records come in time order).
  std::uint32_t can_bitrate() const { return can_bitrate_; }
  std::uint32_t can_begins() const { return can_begins_; }  // can_begin() calls so far
  std::vector<CanRequest> take_can_requests() { return std::exchange(can_requests_, {}); }
  void deliver_can(const sear_link_can& record) { can_records_.push_back(record); }

 private:
  static void setup_link(sear_link& link, const void* self);
  // Bytes between the UART devices and the firmware's ports for [t0, t1), into the link's rx.
  std::uint32_t exchange_serial(std::int64_t t0, std::int64_t t1, sear_link& link, std::uint32_t rx_count);
  void drain(std::size_t index, McuListener& listener);
  // Passes on each reading the firmware's process published since the last turn, once checked;
  // false (the firmware stopped as corrupted, see failure()) at the first bad one.
  bool take_readings();
  void command_actuators();

  McuDesc desc_;
  std::string id_;
  std::size_t index_;
  RunTap* tap_;
  std::vector<std::size_t> input_device_;  // per inputs_ entry: the device whose model it is
  Vehicle& vehicle_;
  std::vector<sear_link_input> inputs_;               // the devices' models in the firmware's process
  std::vector<std::unique_ptr<SimDevice>> devices_;  // desc_.devices, in order
  SampleSink samples_;                               // for the coming quantum
  std::unique_ptr<McuProcess> process_;
  sear_reading_watch reading_watch_{};
  std::optional<McuFailure> reading_failure_;  // a bad reading stopped it (process_ is gone then)
  std::optional<McuHalt> halt_;
  // What the firmware drives on each pin: 0..255 (LOW, PWM duty, HIGH); inputs drive nothing.
  std::array<int, SEAR_LINK_PINS> pin_drive_{};
  std::array<bool, SEAR_LINK_PINS> pin_output_{};
  ServoWires servo_wires_;  // what each servo's pin carries
  std::vector<std::size_t> receive_next_;  // per desc_.uarts entry: the next captured byte to send

  // A UART device on one of the MCU's ports, and the line each way: where the two ends disagree
  // on the rate or the polarity, each reads what a real receiver would.
  struct SerialLink {
    UartDevice* device;
    std::size_t device_index;
    std::uint8_t port;
    HostSerialEnd* host;  // the device's other end, when the host has it instead of the port
    SerialWire to_device;  // the firmware's TX as the device's receiver reads it
    SerialWire to_mcu;     // the device's TX as the port's receiver reads it
    std::uint32_t device_baud;
    std::int64_t baud_since_ns;
    std::uint32_t host_baud = 0;
    std::int64_t host_sent_end_ns = 0;  // the host's bytes leave back to back from here
    // On a soft UART's pins instead of a port: the link input whose model plays the device's
    // frames out on the firmware's RX pin (-1: on a port), and the receiver of its TX pin.
    int soft_input = -1;
    PinUartDecoder from_pin{};
    std::uint64_t soft_bytes = 0;  // sent so far, each one's sample index
  };
  // The host's bytes onto the line into the device, at the host's rate, from t0 on.
  void take_from_host(SerialLink& s, std::int64_t t0, std::int64_t t1);
  std::vector<SerialLink> serial_;
  // Soft UARTs (a UART device given uart="soft:RX,TX"): per device, the link input of its pin
  // model, or -1; per pin, the serial_ entry decoding the firmware's TX there, or -1.
  static int add_soft_uart_input(const DeviceDesc& d, const UartDevice& device, DeviceHost& host);
  void soft_tx_edge(const sear_event& e);
  void soft_uart_out(SerialLink& s, std::int64_t t0, std::int64_t t1);
  std::vector<int> soft_input_;
  std::array<int, SEAR_LINK_PINS> soft_tx_link_{};
  // Tells the line into the device of a rate the device took up, from the instant it did.
  static void note_device_baud(SerialLink& s, std::int64_t now_ns);
  std::array<std::uint32_t, SEAR_LINK_UARTS> port_baud_{};  // the firmware's rate per port, 0 until begun
  std::array<int, SEAR_LINK_PINS> pin_listener_{};          // the device told of writes to a pin, or -1
  std::vector<serial_byte> line_bytes_;                     // scratch, per exchange: decoded bytes
  std::vector<serial_byte> sent_bytes_;                     // scratch: what a device sends in a quantum

  McuUsage usage_;
  void note_usage();  // after each turn
  std::int64_t stdout_check_ns_ = 0;  // the sim time from which the stdout is looked at again

  std::uint32_t can_bitrate_ = 0;
  std::uint32_t can_begins_ = 0;
  std::vector<CanRequest> can_requests_;
  CanRequest can_building_{};  // a frame whose data events are still to come
  std::deque<sear_link_can> can_records_;
};

}  // namespace sear
