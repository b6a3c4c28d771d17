// A tty's line rate as a plain number of bits per second, through Linux's termios2 (TCGETS2/TCSETS2),
// so that standard rates (B9600 ... B4000000) and any other rate a program set with BOTHER read alike.
#pragma once

#include <cstdint>

namespace sear {

// The output rate set on the tty behind fd (on a pty master: the slave's, as they share one
// termios); 0 for B0 ("hang up") or if fd is no tty.
std::uint32_t line_output_baud(int fd);

// Sets both directions to a rate that has no Bxxx constant (BOTHER); false if the kernel refuses.
// Standard rates go through glibc's cfsetspeed, which takes them as numbers.
bool set_line_baud_other(int fd, std::uint32_t baud);

}  // namespace sear
