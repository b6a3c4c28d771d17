// Two decimal digits at a time, for the time stamps a 500 kbaud line makes 50 000 of a simulated
// second: a division by 100 and a two-byte copy in place of two divisions by 10.
#pragma once

#include <cstdint>
#include <cstring>

namespace sear {

// Writes `n` (< 100) as two digits at p.
inline void two_digits(char* p, std::uint32_t n) {
  static constexpr char kPairs[] =
      "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
      "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
      "8081828384858687888990919293949596979899";
  std::memcpy(p, kPairs + 2 * n, 2);
}

}  // namespace sear
