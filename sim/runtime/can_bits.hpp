// A classical CAN frame's bits on the wire (ISO 11898-1): the unstuffed sequence from SOF to the
// end of the data field, its CRC-15, and the length once bit stuffing is applied.
#pragma once

#include <array>
#include <cstdint>

#include "runtime/can_frame.hpp"

namespace sear::can_bits {

// Bits on the wire after the stuffed part: CRC delimiter, ACK slot, ACK delimiter, 7 EOF bits.
constexpr int kTailBits = 10;
// Recessive bits after EOF before any node may start the next SOF.
constexpr int kIntermissionBits = 3;
// After a failed frame's ACK slot: a 6-bit error flag and the 8-bit error delimiter. With nobody
// else listening there is no second flag to superimpose, so the flag keeps its minimum length.
constexpr int kErrorFrameBits = 6 + 8;
// An error-passive transmitter waits this long after intermission before it may start again
// ("suspend transmission", ISO 11898-1 fault confinement).
constexpr int kSuspendBits = 8;
// CRC-15/CAN generator x^15 + x^14 + x^10 + x^8 + x^7 + x^4 + x^3 + 1.
constexpr std::uint16_t kCrc15Polynomial = 0x4599;

// Unstuffed bits, 0 = dominant. The longest, an extended frame with 8 data bytes, is
// 39 + 64 header and data bits and the 15 CRC bits: 118.
struct FrameBits {
  std::array<std::uint8_t, 128> bit{};
  int count = 0;      // SOF .. last CRC bit
  int crc_begin = 0;  // index of the CRC's first bit = bits covered by the CRC
  std::uint16_t crc = 0;
};

// The bits a transmitter sends for `frame` (remote frames carry no data field whatever their
// DLC); `frame.dlc` above 8 is sent as 8 data bytes with that DLC code.
FrameBits unstuffed_bits(const CanFrame& frame);
// CRC-15 over `count` bits, MSB of the register first, initial value 0, as the ISO 11898-1 shift
// register computes it.
std::uint16_t crc15(const std::uint8_t* bits, int count);
// Stuff bits the transmitter inserts into SOF..CRC (a complement after every 5 equal bits, the
// stuff bit starting the next run; one after the CRC's last bit too when it ends a run of 5).
int stuff_bit_count(const FrameBits& bits);
// The frame's bits from SOF to the end of EOF, stuffing included (without intermission).
int wire_bits(const CanFrame& frame);

}  // namespace sear::can_bits
