// termios2 lives in the kernel's <asm/termbits.h>, whose struct termios clashes with glibc's
// <termios.h>: this file is the only one that includes it. glibc 2.36 reports a BOTHER rate as
// the constant BOTHER, not as a number, hence the ioctl rather than cfgetospeed.
#include "pty/line_speed.hpp"

#include <sys/ioctl.h>

#include <asm/termbits.h>

namespace sear {

std::uint32_t line_output_baud(int fd) {
  struct termios2 t {};
  if (ioctl(fd, TCGETS2, &t) != 0) return 0;
  // The kernel fills c_ospeed from the Bxxx bits on every TCSETS, and keeps it for BOTHER.
  return t.c_ospeed;
}

bool set_line_baud_other(int fd, std::uint32_t baud) {
  struct termios2 t {};
  if (ioctl(fd, TCGETS2, &t) != 0) return false;
  // Input bits 0 (CIBAUD clear) mean "the same as output", as a UART with one divisor runs.
  t.c_cflag &= ~static_cast<tcflag_t>(CBAUD | (CBAUD << IBSHIFT));
  t.c_cflag |= BOTHER;
  t.c_ospeed = baud;
  t.c_ispeed = baud;
  return ioctl(fd, TCSETS2, &t) == 0 && line_output_baud(fd) == baud;
}

}  // namespace sear
