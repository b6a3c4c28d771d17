// A simulated UART device's other end as a host pseudo-terminal: PC programs (gpsd, a LIDAR driver)
// open the slave, or the stable link to it, as they would a USB serial adapter.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "runtime/host_serial.hpp"

namespace sear {

// Port semantics follow a real serial port rather than a bare pty:
// - The rate is what the host program set with termios (baud()); until it sets one, the slave
//   runs raw 8N1 at the device's power-up rate, so a program that never touches termios reads
//   clean bytes. A program's settings stay after it closes, as a serial port's do.
// - While no program has the slave open, bytes the device sends are dropped, as a UART whose
//   driver shut its receiver down on the last close; what the last program left unread is
//   flushed when it closes, so the next one starts with an empty buffer. (Linux would otherwise
//   keep up to 4 KiB of stale bytes and hand them all to the next opener at once.)
// - A program that writes and then closes has all its bytes delivered, as close() drains a port.
// - Nothing blocks; a closed slave is seen as the master's EIO / POLLHUP, never polled in a loop.
// Whether a program has the slave open is learnt once per read() or write(): a close and reopen
// within one call's interval looks like no close at all.
class PtyPort final : public HostSerialEnd {
 public:
  // Opens a pty whose slave starts raw at power_up_baud (any rate: a standard one as its Bxxx
  // constant, another as BOTHER) and, unless link_path is empty, points the symlink link_path at
  // it, replacing a symlink left there but never another file. Throws std::runtime_error
  // naming what failed.
  PtyPort(const std::string& link_path, std::uint32_t power_up_baud);
  // Removes the link (if it still points here) and closes the master: a program holding the
  // slave then reads EOF/EIO, as from an unplugged adapter.
  ~PtyPort() override;
  PtyPort(const PtyPort&) = delete;
  PtyPort& operator=(const PtyPort&) = delete;

  // The output rate the slave's termios holds (Linux's serial core also drives a UART from the
  // output rate alone); 0 after B0.
  std::uint32_t baud() override;
  std::size_t read(std::uint8_t* out, std::size_t capacity) override;
  void write(const serial_byte* bytes, std::size_t count) override;

  const std::string& slave_path() const { return slave_path_; }  // /dev/pts/N, different every run
  const std::string& link_path() const { return link_path_; }
  // Whether a program had the slave open when last looked, and how many openings were seen.
  bool host_attached() const { return attached_; }
  std::uint64_t host_opens() const { return opens_; }
  // Bytes the device sent that never reached the host: the pty's buffer was full (the host
  // reads too slowly), or no program had the port open.
  std::uint64_t dropped_unread() const { return dropped_unread_; }
  std::uint64_t dropped_closed() const { return dropped_closed_; }

 private:
  void observe(bool attached_now);
  void flush_unread();

  int master_ = -1;
  std::string slave_path_;
  std::string link_path_;
  bool attached_ = false;
  std::uint64_t opens_ = 0;
  std::uint64_t dropped_unread_ = 0;
  std::uint64_t dropped_closed_ = 0;
};

}  // namespace sear
