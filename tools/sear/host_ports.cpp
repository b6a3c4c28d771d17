#include "sear/host_ports.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "can/socketcan_port.hpp"
#include "pty/pty_port.hpp"
#include "scene/device_kind.hpp"

namespace sear {
namespace {

// The UART device a --pty names, with the baud it powers up at; throws naming those there are.
const DeviceDesc& find_uart_device(const ProjectDesc& project, const std::string& name) {
  std::vector<std::string> known;
  for (const auto& robot : project.robots)
    for (const auto& mcu : robot.mcus)
      for (const auto& d : mcu.devices) {
        // Only a device whose serial line is wired has one to give.
        bool uart = false;
        for (std::size_t w = 0; w < d.kind->wires.size(); ++w)
          uart = uart || (d.kind->wires[w].kind == WireKind::UartPort && d.wires[w] >= 0);
        if (!uart) continue;
        const std::string id = robot.name + "." + mcu.name + "." + d.name;
        if (id == name) return d;
        known.push_back(id);
      }
  throw std::runtime_error(fmt::format("--pty {}: the project has no UART device of that name{}", name,
                                       known.empty() ? std::string(" (it has none)")
                                                     : fmt::format(" (it has: {})", fmt::join(known, ", "))));
}

}  // namespace

HostPorts::HostPorts(const ProjectDesc& project, const std::vector<std::string>& ptys,
                     const std::vector<std::string>& cans, const std::string& out_dir) {
  for (const auto& name : ptys) {
    const DeviceDesc& device = find_uart_device(project, name);
    for (const auto& [taken, end] : ptys_)
      if (taken == name) throw std::runtime_error(fmt::format("--pty {} is given twice", name));
    // The rate the device powers up at (9600 for every serial device in the table unless its
    // row has a 'baud'), so that a host program that sets no termios reads it cleanly.
    std::uint32_t baud = 9600;
    for (std::size_t p = 0; p < device.kind->params.size(); ++p)
      if (std::string(device.kind->params[p].attribute) == "baud") baud = static_cast<std::uint32_t>(device.values[p]);
    auto port = std::make_unique<PtyPort>(out_dir + "/" + name + ".pty", baud);
    listing_.push_back({name, port->slave_path(), port->link_path(), 0});
    ptys_.emplace_back(name, std::move(port));
  }
  for (const auto& spec : cans) {
    // "IFACE" alone names the project's one bus; "BUS=IFACE" picks one of several.
    const auto eq = spec.find('=');
    if (eq == 0 || (eq != std::string::npos && eq + 1 == spec.size()))
      throw std::runtime_error(fmt::format("--can {}: expected IFACE or BUS=IFACE, e.g. vcan0 or body=vcan0", spec));
    if (project.can_buses.empty())
      throw std::runtime_error(fmt::format("--can {}: the project has no <can_bus>", spec));
    if (eq == std::string::npos && project.can_buses.size() != 1)
      throw std::runtime_error(fmt::format("--can {}: the project has {} CAN buses; say which with BUS={}", spec,
                                           project.can_buses.size(), spec));
    const std::string bus = eq == std::string::npos ? project.can_buses[0].name : spec.substr(0, eq);
    const std::string iface = eq == std::string::npos ? spec : spec.substr(eq + 1);
    for (const auto& [taken, end] : cans_)
      if (taken == bus) throw std::runtime_error(fmt::format("--can {}: bus '{}' is bridged twice", spec, bus));
    bool known = false;
    for (const auto& b : project.can_buses) known = known || b.name == bus;
    if (!known) throw std::runtime_error(fmt::format("--can {}: the project has no <can_bus name=\"{}\">", spec, bus));
    try {
      cans_.emplace_back(bus, std::make_unique<SocketCanPort>(iface));
    } catch (const SocketCanError& e) {
      throw std::runtime_error(fmt::format("--can {}: {}", spec, e.what()));
    }
    listing_.push_back({"can_bus " + bus, iface, "", 0});
  }
}

HostPorts::~HostPorts() = default;

std::vector<RunOutcome::HostPort> HostPorts::final_listing() const {
  std::vector<RunOutcome::HostPort> ports = listing_;
  for (std::size_t i = 0; i < ptys_.size(); ++i)
    ports[i].dropped = ptys_[i].second->dropped_unread() + ptys_[i].second->dropped_closed();
  for (std::size_t i = 0; i < cans_.size(); ++i) ports[ptys_.size() + i].dropped = cans_[i].second->dropped();
  return ports;
}

std::map<std::string, HostSerialEnd*> HostPorts::serial_ends() const {
  std::map<std::string, HostSerialEnd*> ends;
  for (const auto& [name, end] : ptys_) ends[name] = end.get();
  return ends;
}

void HostPorts::attach_can(Lockstep& lockstep) const {
  for (const auto& [bus, end] : cans_) lockstep.attach_can_host(bus, end.get());
}

}  // namespace sear
