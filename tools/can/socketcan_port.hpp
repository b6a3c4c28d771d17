// A raw SocketCAN socket on one host interface (vcan0, can0), the host end of `sear run --can`:
// classical CAN frames in and out, never blocking the run loop on reads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "runtime/can_frame.hpp"
#include "runtime/host_can.hpp"

namespace sear {

// Says what is missing or wrong in the host's CAN setup, in words a user can act on.
class SocketCanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class SocketCanPort final : public HostCanEnd {
 public:
  // Opens a raw CAN socket bound to `interface`. Throws SocketCanError: "this kernel has no
  // SocketCAN (...)", "no CAN interface 'vcan0' (...)", "'eth0' is not a CAN interface",
  // "CAN interface 'can0' is down (...)".
  explicit SocketCanPort(const std::string& interface);
  ~SocketCanPort() override;
  SocketCanPort(SocketCanPort&& other) noexcept;
  SocketCanPort& operator=(SocketCanPort&& other) noexcept;
  SocketCanPort(const SocketCanPort&) = delete;
  SocketCanPort& operator=(const SocketCanPort&) = delete;

  // Appends every frame waiting on the socket to `out`, oldest first, and returns how many; never
  // blocks (0 when none is waiting). Frames sent through this same port are not read back.
  std::size_t read_available(std::vector<CanFrame>& out) override;
  // Sends one frame (id, dlc and flags checked first). Waits, bounded, while the interface's
  // transmit queue is full; throws SocketCanError when it stays full or the interface goes down.
  void write(const CanFrame& frame) override;

  // Frames the kernel dropped for this socket since it was opened, because its receive queue was
  // full (the socket's drop count, SO_MEMINFO); as of the last read_available().
  std::uint32_t dropped() const { return dropped_; }
  const std::string& interface() const { return interface_; }
  // For poll(): readable when read_available() has frames to give.
  int fd() const { return fd_; }

 private:
  void close_socket() noexcept;

  int fd_ = -1;
  std::string interface_;
  std::uint32_t dropped_ = 0;
};

}  // namespace sear
