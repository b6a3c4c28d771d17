// PtyPort: posix_openpt and friends, plus what a bare pty lacks to behave as a serial port.
#include "pty/pty_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "pty/line_speed.hpp"

namespace sear {

namespace {

std::string errno_text(const std::string& what) { return what + ": " + std::strerror(errno); }

// The target of the symlink at path, or "" if there is none.
std::string link_target(const std::string& path) {
  std::array<char, 4096> buf{};
  const ssize_t n = ::readlink(path.c_str(), buf.data(), buf.size() - 1);
  return n > 0 ? std::string(buf.data(), static_cast<std::size_t>(n)) : std::string();
}

}  // namespace

PtyPort::PtyPort(const std::string& link_path, std::uint32_t power_up_baud) : link_path_(link_path) {
  // O_CLOEXEC on top of the usual flags: firmware processes started later must not hold the
  // master, or the pty would outlive the run in them.
  master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (master_ < 0) throw std::runtime_error(errno_text("cannot open a pseudo-terminal (posix_openpt)"));
  auto fail = [this](const std::string& what) {
    const std::string text = errno_text(what);
    ::close(master_);
    throw std::runtime_error(text);
  };
  if (::grantpt(master_) != 0 || ::unlockpt(master_) != 0) fail("cannot unlock the pseudo-terminal's slave");
  std::array<char, 128> name{};
  if (::ptsname_r(master_, name.data(), name.size()) != 0) fail("cannot name the pseudo-terminal's slave");
  slave_path_ = name.data();

  // The master's termios calls act on the slave's termios (Linux keeps one per pair).
  termios t{};
  if (::tcgetattr(master_, &t) != 0) fail("cannot read the pseudo-terminal's settings");
  ::cfmakeraw(&t);
  // glibc takes standard rates as plain numbers; the others need termios2's BOTHER.
  const bool standard = ::cfsetspeed(&t, power_up_baud) == 0;
  if (::tcsetattr(master_, TCSANOW, &t) != 0) fail("cannot set the pseudo-terminal raw");
  if (!standard && !set_line_baud_other(master_, power_up_baud))
    fail("cannot set the pseudo-terminal to " + std::to_string(power_up_baud) + " baud");

  // Linux reports "nobody has the slave open" (EIO, POLLHUP) only once it has been closed: until
  // then a fresh pty takes bytes and keeps them for its first opener. One open and close puts it
  // in the state every later close leaves it in.
  const int slave = ::open(slave_path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (slave < 0) fail("cannot open " + slave_path_);
  ::close(slave);

  if (link_path_.empty()) return;
  struct stat st {};
  if (::lstat(link_path_.c_str(), &st) == 0 && !S_ISLNK(st.st_mode)) {
    errno = EEXIST;
    fail("will not replace " + link_path_ + " with a link to the pseudo-terminal");
  }
  // Through a temporary name and rename(), so the link is never missing nor half made.
  const std::string temporary = link_path_ + ".new" + std::to_string(::getpid());
  ::unlink(temporary.c_str());
  if (::symlink(slave_path_.c_str(), temporary.c_str()) != 0) fail("cannot create the link " + temporary);
  if (::rename(temporary.c_str(), link_path_.c_str()) != 0) {
    const int saved = errno;
    ::unlink(temporary.c_str());
    errno = saved;
    fail("cannot create the link " + link_path_);
  }
}

PtyPort::~PtyPort() {
  if (!link_path_.empty() && link_target(link_path_) == slave_path_) ::unlink(link_path_.c_str());
  ::close(master_);
}

std::uint32_t PtyPort::baud() { return line_output_baud(master_); }

std::size_t PtyPort::read(std::uint8_t* out, std::size_t capacity) {
  std::size_t n = 0;
  while (n < capacity) {
    const ssize_t got = ::read(master_, out + n, capacity - n);
    if (got > 0) {
      n += static_cast<std::size_t>(got);
      observe(true);
      continue;
    }
    if (got < 0 && errno == EINTR) continue;
    // EAGAIN: open, nothing to read. EIO: nobody has the slave open (after what they wrote).
    if (got < 0 && errno == EAGAIN) observe(true);
    if (got < 0 && errno == EIO) observe(false);
    break;
  }
  return n;
}

void PtyPort::write(const serial_byte* bytes, std::size_t count) {
  if (count == 0) return;
  pollfd p{master_, 0, 0};
  if (::poll(&p, 1, 0) >= 0) observe((p.revents & POLLHUP) == 0);
  if (!attached_) {
    dropped_closed_ += count;
    return;
  }
  std::array<std::uint8_t, 256> chunk{};
  for (std::size_t done = 0; done < count;) {
    const std::size_t m = std::min(chunk.size(), count - done);
    for (std::size_t i = 0; i < m; ++i) chunk[i] = bytes[done + i].value;
    ssize_t put = ::write(master_, chunk.data(), m);
    if (put < 0 && errno == EINTR) continue;
    if (put < 0) put = 0;  // EAGAIN: the buffer is full; EIO: closed meanwhile
    done += static_cast<std::size_t>(put);
    if (static_cast<std::size_t>(put) < m) {
      dropped_unread_ += count - done;
      return;
    }
  }
}

void PtyPort::observe(bool attached_now) {
  if (attached_now && !attached_) ++opens_;
  if (!attached_now && attached_) flush_unread();
  attached_ = attached_now;
}

void PtyPort::flush_unread() {
  // The pty keeps the slave's input queue across closes; a serial port's driver frees its buffers
  // on the last close. The master cannot flush the slave's input, so open the slave to do it.
  // Only input: what the program wrote before closing is the master's, and is still delivered.
  const int slave = ::open(slave_path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (slave < 0) return;  // a program holds it exclusively (TIOCEXCL): then it is open anyway
  ::tcflush(slave, TCIFLUSH);
  ::close(slave);
}

}  // namespace sear
