// Drives SocketCanPort against a real kernel for vcan_test.cpp, which runs it where vcan0 exists
// (natively or in the qemu guest) and checks what it prints against candump and cansend.
//   socketcan_probe send IFACE            writes the frames of kFrames, in order
//   socketcan_probe recv IFACE N READY    touches READY once bound, prints N frames in cansend syntax
//   socketcan_probe burst IFACE           one port writes, another reads: batching and drop count
//   socketcan_probe fill IFACE N          writes N numbered frames; prints how many went, and the error
//   socketcan_probe errors                prints the errors for a missing and a non-CAN interface
#include <fmt/format.h>
#include <poll.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "can/socketcan_port.hpp"

namespace {

using sear::CanFrame;

CanFrame make(std::uint32_t id, bool extended, bool remote, std::vector<std::uint8_t> data, int dlc = -1) {
  CanFrame f;
  f.id = id;
  f.extended = extended;
  f.remote = remote;
  f.dlc = static_cast<std::uint8_t>(dlc >= 0 ? dlc : static_cast<int>(data.size()));
  for (std::size_t i = 0; i < data.size(); ++i) f.data[i] = data[i];
  return f;
}

// Every kind of classical frame: both id widths at their limits, an extended id small enough to
// pass for a standard one, remote frames with and without a requested length, and dlc 0..8.
std::vector<CanFrame> sent_frames() {
  std::vector<CanFrame> frames = {
      make(0x123, false, false, {0xDE, 0xAD, 0xBE, 0xEF}),
      make(0x000, false, false, {}),
      make(0x7FF, false, false, {1, 2, 3, 4, 5, 6, 7, 8}),
      make(0x1FFFFFFF, true, false, {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF}),
      make(0x00000001, true, false, {0x00}),
      make(0x321, false, true, {}),
      make(0x18DAF110, true, true, {}, 3),
  };
  for (std::uint8_t dlc = 0; dlc <= 8; ++dlc) {
    std::vector<std::uint8_t> data;
    for (std::uint8_t i = 0; i < dlc; ++i) data.push_back(static_cast<std::uint8_t>(dlc * 16 + i));
    frames.push_back(make(0x200u + dlc, false, false, data));
  }
  return frames;
}

// cansend's syntax, which candump -L also prints: 3 hex digits for a standard id, 8 for extended.
std::string cansend_syntax(const CanFrame& f) {
  std::string text = f.extended ? fmt::format("{:08X}#", f.id) : fmt::format("{:03X}#", f.id);
  if (f.remote) return text + "R" + (f.dlc > 0 ? std::to_string(f.dlc) : "");
  for (int i = 0; i < f.dlc; ++i) text += fmt::format("{:02X}", f.data[i]);
  return text;
}

bool wait_readable(const sear::SocketCanPort& port, int ms) {
  pollfd p{port.fd(), POLLIN, 0};
  return ::poll(&p, 1, ms) > 0;
}

int recv(const std::string& iface, int count, const std::string& ready) {
  sear::SocketCanPort port(iface);
  std::ofstream(ready) << "bound\n";
  std::vector<CanFrame> frames;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (static_cast<int>(frames.size()) < count && std::chrono::steady_clock::now() < give_up)
    if (wait_readable(port, 100)) port.read_available(frames);
  for (const auto& f : frames) std::printf("%s\n", cansend_syntax(f).c_str());
  std::printf("dropped %u\n", port.dropped());
  return static_cast<int>(frames.size()) == count ? 0 : 1;
}

// A burst far smaller than a socket's receive queue arrives whole through one read_available()
// (more than one recvmmsg batch); one far larger overflows it, and the kernel's drop count
// accounts for every frame not read.
int burst(const std::string& iface) {
  sear::SocketCanPort writer(iface);
  sear::SocketCanPort reader(iface);
  auto numbered = [](int i) {
    return make(static_cast<std::uint32_t>(i), true, false,
                {static_cast<std::uint8_t>(i >> 8), static_cast<std::uint8_t>(i & 0xFF)});
  };
  for (const int total : {150, 5000}) {
    const std::uint32_t dropped_before = reader.dropped();
    for (int i = 0; i < total; ++i) writer.write(numbered(i));
    // vcan hands each frame to the receivers before write() returns; the wait only covers a
    // kernel that defers it to its softirq.
    wait_readable(reader, 1000);
    std::vector<CanFrame> frames;
    const std::size_t first_call = reader.read_available(frames);
    int in_order = 0;
    while (in_order < static_cast<int>(frames.size()) && frames[in_order] == numbered(in_order)) ++in_order;
    std::vector<CanFrame> more;
    const std::size_t second_call = reader.read_available(more);
    std::printf("burst %d: first_call %zu in_order %d second_call %zu dropped %u\n", total, first_call, in_order,
                second_call, reader.dropped() - dropped_before);
  }
  return 0;
}

// Numbered frames into a transmit queue that may be full: prints how many write() took, and the
// error that stopped it, if any.
int fill(const std::string& iface, int count) {
  sear::SocketCanPort port(iface);
  int written = 0;
  try {
    for (; written < count; ++written)
      port.write(make(static_cast<std::uint32_t>(written), true, false,
                      {static_cast<std::uint8_t>(written >> 8), static_cast<std::uint8_t>(written & 0xFF)}));
    std::printf("wrote %d\n", written);
  } catch (const sear::SocketCanError& e) {
    std::printf("wrote %d\nerror: %s\n", written, e.what());
  }
  return 0;
}

int errors() {
  for (const char* name : {"nocan0", "lo"}) {
    try {
      sear::SocketCanPort port(name);
      std::printf("%s: opened\n", name);
    } catch (const sear::SocketCanError& e) {
      std::printf("%s: %s\n", name, e.what());
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.size() == 2 && args[0] == "send") {
      sear::SocketCanPort port(args[1]);
      for (const auto& f : sent_frames()) port.write(f);
      return 0;
    }
    if (args.size() == 4 && args[0] == "recv") return recv(args[1], std::atoi(args[2].c_str()), args[3]);
    if (args.size() == 2 && args[0] == "burst") return burst(args[1]);
    if (args.size() == 3 && args[0] == "fill") return fill(args[1], std::atoi(args[2].c_str()));
    if (args.size() == 1 && args[0] == "errors") return errors();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "socketcan_probe: %s\n", e.what());
    return 2;
  }
  std::fprintf(stderr, "usage: socketcan_probe send IFACE | recv IFACE N READY | burst IFACE | fill IFACE N | errors\n");
  return 2;
}
