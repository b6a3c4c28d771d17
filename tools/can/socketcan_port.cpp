// A raw SocketCAN socket on one host interface; see socketcan_port.hpp.
#include "can/socketcan_port.hpp"

#include <fmt/format.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <linux/sock_diag.h>
#include <net/if.h>
#include <net/if_arp.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <utility>

namespace sear {

namespace {

// Frames fetched per recvmmsg() call. The densest traffic a 1 Mbit/s bus carries is back-to-back
// standard frames with no data, 47 bits each (44 + 3 bits of interframe space), so ~21 frames per
// 1 ms quantum: one batch holds three quanta of a saturated bus.
constexpr unsigned kBatch = 64;

// How long write() keeps retrying while the interface's transmit queue stays full. At 10 kbit/s, the
// slowest rate hal/can.h offers, a full default queue (txqueuelen 10) of the longest classical
// frames (extended, 8 bytes: 131 bits, ~160 with worst-case stuffing) drains in 160 ms; a queue
// still full after a second means no frame is leaving at all (no other node acknowledges, or the
// controller is bus-off), and waiting longer would only stall the run.
constexpr std::chrono::milliseconds kFullQueueWait{1000};

std::string errno_text(int error) { return std::strerror(error); }

std::string missing_interface_hint(const std::string& name) {
  if (name.rfind("vcan", 0) == 0)
    return fmt::format("a virtual one is made with `ip link add dev {0} type vcan && ip link set up {0}`", name);
  return "`ip -details link show` lists the interfaces and their kinds";
}

}  // namespace

SocketCanPort::SocketCanPort(const std::string& interface) : interface_(interface) {
  fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd_ < 0) {
    const int error = errno;
    if (error == EAFNOSUPPORT || error == EPROTONOSUPPORT)
      throw SocketCanError(fmt::format(
          "this kernel has no SocketCAN (socket(AF_CAN) failed: {}); it needs the modules can and can-raw",
          errno_text(error)));
    throw SocketCanError(fmt::format("cannot open a CAN socket: {}", errno_text(error)));
  }
  try {
    if (interface.empty() || interface.size() >= IFNAMSIZ)
      throw SocketCanError(fmt::format("no CAN interface '{}' (interface names have 1 to {} characters)",
                                       interface, IFNAMSIZ - 1));
    const unsigned index = ::if_nametoindex(interface.c_str());
    if (index == 0)
      throw SocketCanError(fmt::format("no CAN interface '{}' ({}; {})", interface, errno_text(errno),
                                       missing_interface_hint(interface)));

    ifreq request{};
    std::memcpy(request.ifr_name, interface.c_str(), interface.size() + 1);
    // The CAN socket itself answers no ioctl; the kernel passes these on to the network device.
    if (::ioctl(fd_, SIOCGIFHWADDR, &request) < 0)
      throw SocketCanError(fmt::format("cannot ask '{}' for its link type: {}", interface, errno_text(errno)));
    if (request.ifr_hwaddr.sa_family != ARPHRD_CAN)
      throw SocketCanError(fmt::format("'{}' is not a CAN interface (its link type is {}, CAN's is {})", interface,
                                       request.ifr_hwaddr.sa_family, ARPHRD_CAN));
    if (::ioctl(fd_, SIOCGIFFLAGS, &request) < 0)
      throw SocketCanError(fmt::format("cannot ask '{}' whether it is up: {}", interface, errno_text(errno)));
    if (!(request.ifr_flags & IFF_UP))
      throw SocketCanError(fmt::format(
          "CAN interface '{0}' is down (`ip link set up {0}`; a real controller also needs its bit rate: "
          "`ip link set {0} up type can bitrate 500000`)",
          interface));

    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = static_cast<int>(index);
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) < 0)
      throw SocketCanError(fmt::format("cannot bind a CAN socket to '{}': {}", interface, errno_text(errno)));
  } catch (...) {
    close_socket();
    throw;
  }
}

SocketCanPort::~SocketCanPort() { close_socket(); }

SocketCanPort::SocketCanPort(SocketCanPort&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), interface_(std::move(other.interface_)), dropped_(other.dropped_) {}

SocketCanPort& SocketCanPort::operator=(SocketCanPort&& other) noexcept {
  if (this != &other) {
    close_socket();
    fd_ = std::exchange(other.fd_, -1);
    interface_ = std::move(other.interface_);
    dropped_ = other.dropped_;
  }
  return *this;
}

void SocketCanPort::close_socket() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

std::size_t SocketCanPort::read_available(std::vector<CanFrame>& out) {
  can_frame frames[kBatch];
  iovec vectors[kBatch];
  mmsghdr messages[kBatch];
  std::size_t count = 0;
  for (;;) {
    for (unsigned i = 0; i < kBatch; ++i) {
      vectors[i] = {&frames[i], sizeof frames[i]};
      messages[i] = {};
      messages[i].msg_hdr.msg_iov = &vectors[i];
      messages[i].msg_hdr.msg_iovlen = 1;
    }
    const int received = ::recvmmsg(fd_, messages, kBatch, MSG_DONTWAIT, nullptr);
    if (received < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) break;
      throw SocketCanError(fmt::format("reading CAN interface '{}' failed: {}", interface_, errno_text(errno)));
    }
    for (int i = 0; i < received; ++i) {
      // Only classical frames reach a socket that did not ask for CAN FD; anything else is not ours.
      if (messages[i].msg_len != sizeof(can_frame)) continue;
      const can_frame& raw = frames[i];
      if (raw.can_id & CAN_ERR_FLAG) continue;
      CanFrame frame;
      frame.extended = (raw.can_id & CAN_EFF_FLAG) != 0;
      frame.remote = (raw.can_id & CAN_RTR_FLAG) != 0;
      frame.id = raw.can_id & (frame.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
      frame.dlc = raw.len > CAN_MAX_DLEN ? CAN_MAX_DLEN : raw.len;
      if (!frame.remote) std::memcpy(frame.data.data(), raw.data, frame.dlc);
      out.push_back(frame);
      ++count;
    }
    if (received < static_cast<int>(kBatch)) break;
  }
  // SO_RXQ_OVFL would only tell, with the next frame queued after them, of drops that happened
  // before it; SO_MEMINFO says how many there have been up to now.
  std::uint32_t meminfo[SK_MEMINFO_VARS] = {};
  socklen_t size = sizeof meminfo;
  if (::getsockopt(fd_, SOL_SOCKET, SO_MEMINFO, meminfo, &size) == 0 && size > SK_MEMINFO_DROPS * sizeof(std::uint32_t))
    dropped_ = meminfo[SK_MEMINFO_DROPS];
  return count;
}

void SocketCanPort::write(const CanFrame& frame) {
  const std::uint32_t id_limit = frame.extended ? CAN_EFF_MASK : CAN_SFF_MASK;
  if (frame.id > id_limit)
    throw std::invalid_argument(fmt::format("CAN id {:#x} does not fit {} bits", frame.id, frame.extended ? 29 : 11));
  if (frame.dlc > CAN_MAX_DLEN) throw std::invalid_argument(fmt::format("CAN dlc {} is over 8", frame.dlc));
  can_frame raw{};
  raw.can_id = frame.id | (frame.extended ? CAN_EFF_FLAG : 0U) | (frame.remote ? CAN_RTR_FLAG : 0U);
  raw.len = frame.dlc;  // a remote frame's dlc says how much it asks for
  if (!frame.remote) std::memcpy(raw.data, frame.data.data(), frame.dlc);

  const auto give_up = std::chrono::steady_clock::now() + kFullQueueWait;
  for (;;) {
    const ssize_t sent = ::send(fd_, &raw, sizeof raw, MSG_DONTWAIT);
    if (sent == static_cast<ssize_t>(sizeof raw)) return;
    const int error = sent < 0 ? errno : EIO;
    if (error == EINTR) continue;
    if (error != ENOBUFS && error != EAGAIN && error != EWOULDBLOCK) {
      if (error == ENETDOWN)
        throw SocketCanError(fmt::format("CAN interface '{0}' went down (`ip link set up {0}`)", interface_));
      throw SocketCanError(fmt::format("writing to CAN interface '{}' failed: {}", interface_, errno_text(error)));
    }
    if (std::chrono::steady_clock::now() >= give_up)
      throw SocketCanError(fmt::format(
          "CAN interface '{}' stayed full for {} ms: no frame is leaving it (is another node acknowledging? "
          "`ip -details -statistics link show {}` shows the controller's state)",
          interface_, kFullQueueWait.count(), interface_));
    // EAGAIN is the socket's own send buffer, which poll() watches. ENOBUFS is the device's queue
    // (the driver stopped it and the qdisc in front is full), which no poll() event reports: retry
    // each millisecond, about the time one frame takes on the wire at 125 kbit/s.
    pollfd waiting{fd_, POLLOUT, 0};
    ::poll(error == ENOBUFS ? nullptr : &waiting, error == ENOBUFS ? 0 : 1, 1);
  }
}

}  // namespace sear
