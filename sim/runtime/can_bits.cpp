#include "runtime/can_bits.hpp"

#include <algorithm>

namespace sear::can_bits {

namespace {

void put(FrameBits& b, std::uint32_t value, int width) {
  for (int i = width - 1; i >= 0; --i) b.bit[static_cast<std::size_t>(b.count++)] = (value >> i) & 1u;
}

}  // namespace

FrameBits unstuffed_bits(const CanFrame& frame) {
  FrameBits b;
  const std::uint32_t rtr = frame.remote ? 1 : 0;
  put(b, 0, 1);  // SOF, dominant
  if (frame.extended) {
    const std::uint32_t id = frame.id & 0x1FFFFFFFu;
    put(b, id >> 18, 11);  // base identifier
    put(b, 1, 1);          // SRR, recessive
    put(b, 1, 1);          // IDE, recessive
    put(b, id & 0x3FFFFu, 18);
    put(b, rtr, 1);
    put(b, 0, 2);  // r1 r0, sent dominant
  } else {
    put(b, frame.id & 0x7FFu, 11);
    put(b, rtr, 1);
    put(b, 0, 1);  // IDE, dominant
    put(b, 0, 1);  // r0
  }
  put(b, frame.dlc & 0xFu, 4);
  const int data_bytes = frame.remote ? 0 : std::min<int>(frame.dlc, 8);
  for (int i = 0; i < data_bytes; ++i) put(b, frame.data[static_cast<std::size_t>(i)], 8);
  b.crc_begin = b.count;
  b.crc = crc15(b.bit.data(), b.count);
  put(b, b.crc, 15);
  return b;
}

std::uint16_t crc15(const std::uint8_t* bits, int count) {
  std::uint16_t reg = 0;
  for (int i = 0; i < count; ++i) {
    const bool feedback = ((reg >> 14) & 1u) != bits[i];
    reg = static_cast<std::uint16_t>((reg << 1) & 0x7FFF);
    if (feedback) reg ^= kCrc15Polynomial;
  }
  return reg;
}

int stuff_bit_count(const FrameBits& bits) {
  int stuffed = 0;
  int run = 0;
  std::uint8_t last = 2;  // matches no bit
  for (int i = 0; i < bits.count; ++i) {
    const std::uint8_t v = bits.bit[static_cast<std::size_t>(i)];
    run = v == last ? run + 1 : 1;
    last = v;
    if (run == 5) {
      ++stuffed;
      // The stuff bit is the complement and begins the next run.
      last = static_cast<std::uint8_t>(!v);
      run = 1;
    }
  }
  return stuffed;
}

int wire_bits(const CanFrame& frame) {
  const FrameBits bits = unstuffed_bits(frame);
  return bits.count + stuff_bit_count(bits) + kTailBits;
}

}  // namespace sear::can_bits
