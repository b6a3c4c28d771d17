// The run's ends on the host: UART devices given to host programs as pseudo-terminals (--pty)
// and CAN buses bridged to SocketCAN interfaces (--can).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "exporters/run_summary.hpp"
#include "runtime/host_can.hpp"
#include "runtime/host_serial.hpp"
#include "runtime/lockstep.hpp"
#include "scene/description.hpp"

namespace sear {

class PtyPort;
class SocketCanPort;

class HostPorts {
 public:
  // `ptys`: "robot.mcu.device" of UART devices; `cans`: "bus=interface". Opens them all, or
  // throws std::runtime_error saying which is not in the project, or what the host lacks.
  HostPorts(const ProjectDesc& project, const std::vector<std::string>& ptys, const std::vector<std::string>& cans,
            const std::string& out_dir);
  ~HostPorts();

  // For McuRunOptions::host_serial.
  std::map<std::string, HostSerialEnd*> serial_ends() const;
  void attach_can(Lockstep& lockstep) const;
  const std::vector<RunOutcome::HostPort>& listing() const { return listing_; }
  // The same, with what each end lost so far: a pty's bytes that nobody read or that came while
  // nobody had it open, an interface's frames its kernel queue dropped.
  std::vector<RunOutcome::HostPort> final_listing() const;

 private:
  std::vector<std::pair<std::string, std::unique_ptr<PtyPort>>> ptys_;
  std::vector<std::pair<std::string, std::unique_ptr<SocketCanPort>>> cans_;
  std::vector<RunOutcome::HostPort> listing_;
};

}  // namespace sear
