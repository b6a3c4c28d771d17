// The serial line between mismatched UARTs (sim/runtime/serial_wire) against hand-decoded bit
// patterns of an AVR USART receiver (ATmega2560 datasheet, "Asynchronous Data Reception").
// Every expected byte below was also reproduced by an independent 16x-oversampling receiver
// written in Python for this test (not part of the repository); see the report.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "devices/maxbotix_lv_ez.h"
#include "devices/serial_byte.h"
#include "runtime/serial_wire.hpp"

namespace {

using sear::SerialWire;

serial_byte byte_at(int64_t end_ns, uint32_t baud, uint8_t value) { return serial_byte{end_ns, baud, value, {0, 0, 0}}; }

// Start of bit j of a frame starting at start_ns: the 8N1 bit grid, rounded as the wire does.
int64_t bit_time(int64_t start_ns, int j, uint32_t baud) {
  return start_ns + (j * INT64_C(1000000000) + baud / 2) / baud;
}

std::vector<serial_byte> receive_all(SerialWire& wire, int64_t until_ns) {
  std::vector<serial_byte> out;
  wire.receive_until(until_ns, out);
  return out;
}

// What `wire`, its receiver begun at rx_baud from the start, reads of all of `sent` by until_ns;
// the wire is the caller's so that its framing errors can be checked after.
std::vector<serial_byte> read_through(SerialWire& wire, uint32_t rx_baud, const std::vector<serial_byte>& sent,
                                      int64_t until_ns) {
  wire.set_receiver_baud(rx_baud, 0);
  for (const serial_byte& b : sent) wire.send(b);
  return receive_all(wire, until_ns);
}

// When the single 9600-baud bytes of the mismatched-rate tests start.
constexpr int64_t kStart_ns = 1000000;

// A byte sent at 9600 baud from kStart_ns, as `wire` reads it at rx_baud by until_ns.
std::vector<serial_byte> read_9600_byte(SerialWire& wire, uint32_t rx_baud, uint8_t value, int64_t until_ns) {
  return read_through(wire, rx_baud, {byte_at(kStart_ns + serial_frame_ns(9600), 9600, value)}, until_ns);
}

// Same rate, normal polarity: every byte comes out as sent, same value, same time, whether the
// bytes are back to back or spaced, and whatever batches they arrive in.
TEST(SerialWire, MatchingRatesPassBytesThroughExactly) {
  const uint32_t baud = 9600;
  const int64_t frame = serial_frame_ns(baud);
  std::vector<serial_byte> sent;
  int64_t end = 5000000;
  for (int i = 0; i < 600; ++i) {
    // All 256 values, some back to back and some with odd gaps (0..2.9 frames).
    end += frame + (i % 3 == 0 ? 0 : (i * 7919) % (3 * frame));
    sent.push_back(byte_at(end, baud, static_cast<uint8_t>(i * 37 + 11)));
  }
  SerialWire wire(false);
  wire.set_receiver_baud(baud, 0);
  std::vector<serial_byte> got;
  size_t next = 0;
  // 1 ms quanta: the sender gives the bytes ending in each quantum, then the receiver reads.
  for (int64_t q_end = 1000000; q_end <= end + 2000000; q_end += 1000000) {
    while (next < sent.size() && sent[next].end_ns < q_end) wire.send(sent[next++]);
    const size_t before = got.size();
    wire.receive_until(q_end, got);
    for (size_t i = before; i < got.size(); ++i) ASSERT_LT(got[i].end_ns, q_end);
  }
  ASSERT_EQ(got.size(), sent.size());
  for (size_t i = 0; i < sent.size(); ++i) {
    EXPECT_EQ(got[i].value, sent[i].value) << i;
    EXPECT_EQ(got[i].end_ns, sent[i].end_ns) << i;  // exact: same baud, same grid
    EXPECT_EQ(got[i].baud, baud);
  }
  EXPECT_EQ(wire.framing_errors(), 0u);
}

// An ATmega2560 at 16 MHz asked for 9600 baud makes 2 MHz / 208 = 9615.38 baud (UBRR 207, U2X)
// and says 9615 on the line; its back-to-back frames, stamped at its true 1040000 ns each, are
// 42 ns shorter than 9615's 1040042 ns, so each would seem to start before the one before it
// ended. A 9600 receiver (0.16 % off, well within the datasheet's +-2 %) still reads every byte:
// here the LMS2xx request 02 00 02 00 20 25 35 08 that once lost its third byte, its start
// edge hidden behind where the receiver resumed hunting, in the 1 ms quanta of the bridge.
TEST(SerialWire, BackToBackFramesAtARoundedRateAreEachReadFromTheirStart) {
  const uint8_t request[] = {0x02, 0x00, 0x02, 0x00, 0x20, 0x25, 0x35, 0x08};
  const int64_t true_frame = 1040000;  // 10 bits x 16e6 / (8 x 208) ns
  std::vector<serial_byte> sent;
  for (int i = 0; i < 8; ++i) sent.push_back(byte_at(2022612062 + i * true_frame, 9615, request[i]));
  SerialWire wire(false);
  wire.set_receiver_baud(9600, 0);
  std::vector<serial_byte> got;
  size_t next = 0;
  for (int64_t q_end = 2021000000; q_end <= 2040000000; q_end += 1000000) {
    while (next < sent.size() && sent[next].end_ns < q_end + 2 * true_frame) wire.send(sent[next++]);
    wire.receive_until(q_end, got);
  }
  ASSERT_EQ(got.size(), sent.size());
  for (size_t i = 0; i < sent.size(); ++i) EXPECT_EQ(got[i].value, sent[i].value) << i;
  EXPECT_EQ(wire.framing_errors(), 0u);
}

// A receiver begun in the middle of a stream at its own rate: 0x0F back to back at 9600, the
// port begun 2.5 bits into the first frame. Bits of each frame: start 0, data 1 1 1 1 0 0 0 0,
// stop 1. The line is high there (d0..d3) and falls at 5 bits (d4): a start edge, confirmed low at
// 5.53. Its data are sampled at 6.53 (d5 0), 7.53 (d6 0), 8.53 (d7 0), 9.53 (stop 1), then in the
// next frame 10.53 (start 0), 11.53 (d0 1), 12.53 (d1 1), 13.53 (d2 1): 0b11101000 = 0xE8, its
// stop at 14.53 (d3 1), ending 10 bits after its edge, at 15 bits. The hunt resumes 9.59 bits
// after the edge, 4.59 bits into the next frame, before its own fall at 5 bits: each frame is read
// so, never as sent, as a chip's USART begun mid-stream would.
TEST(SerialWire, APortBegunInTheMiddleOfAStreamAtItsRateReadsEachFrameFromItsFirstFall) {
  const uint32_t baud = 9600;
  const int64_t frame = serial_frame_ns(baud);
  const int64_t first_start = 3000000;
  constexpr int kFrames = 12;
  SerialWire wire(false);
  wire.set_receiver_baud(0, 0);
  const int64_t bit2 = bit_time(first_start, 2, baud), bit3 = bit_time(first_start, 3, baud);
  wire.set_receiver_baud(baud, bit2 + (bit3 - bit2) / 2);
  for (int i = 0; i < kFrames; ++i) wire.send(byte_at(first_start + (i + 1) * frame, baud, 0x0F));
  // Up to the last frame's start: frame i's byte ends 5 bits into frame i + 1, so the bytes of
  // all frames but the last two are in.
  const std::vector<serial_byte> got = receive_all(wire, first_start + (kFrames - 1) * frame);
  ASSERT_EQ(got.size(), static_cast<size_t>(kFrames - 2));
  for (int i = 0; i + 2 < kFrames; ++i) {
    EXPECT_EQ(got[i].value, 0xE8) << i;
    EXPECT_EQ(got[i].end_ns, bit_time(first_start + i * frame, 15, baud)) << i;
  }
  EXPECT_EQ(wire.framing_errors(), 0u);
}

// '5' (0x35) sent at 9600 and read at 19200. Sender bits, 104.17 us each (T): start 0, data
// LSB first 1 0 1 0 1 1 0 0, stop 1. The receiver's bits are T/2; it samples 17/32 into each,
// at (k/2 + 0.27) T from the start edge, i.e. twice per sender bit:
//   k:            0  1  2  3  4  5  6  7  8 | 9 (stop)
//   sender bit:   S  S  d0 d0 d1 d1 d2 d2 d3| d3
//   level:        0  0  1  1  0  0  1  1  0 | 0   -> data 0b01100110 = 0x66, framing error
// It hunts again from 4.80 T: the line is low (d3), rises at 5 T (d4), falls at 7 T (d6 = 0):
// a second start edge at 7 T, sampled at 7.27 T (d6 = 0: a start), 7.77 (d6 0), 8.27 (d7 0),
// 8.77 (d7 0), 9.27 (stop 1) and idle 1 from there: data 0b11111000 = 0xF8, stop 1.
// Each ends 10 receiver bits (5 T) after its start edge.
TEST(SerialWire, NineSixHundredReadAtNineteenTwoHundredGivesThePredictedGarbage) {
  SerialWire wire(false);
  const std::vector<serial_byte> got = read_9600_byte(wire, 19200, '5', kStart_ns + 30 * 104167);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].value, 0x66);
  EXPECT_EQ(got[0].end_ns, kStart_ns + serial_frame_ns(19200));
  EXPECT_EQ(got[1].value, 0xF8);
  EXPECT_EQ(got[1].end_ns, bit_time(kStart_ns, 7, 9600) + serial_frame_ns(19200));
  EXPECT_EQ(got[0].baud, 19200u);
  EXPECT_EQ(wire.framing_errors(), 1u);
}

// A stream read as sent while the rates match stops being read so the moment the receiver
// changes its rate: the frames whose start edges come after the change are read at the new
// rate, as a receiver begun then at that rate reads them from the idle line (the line is idle
// between the stop bit the receiver last sampled and the next start edge).
TEST(SerialWire, AReceiversChangeOfRateMidStreamReadsTheFramesAfterItAtTheNewRate) {
  const int64_t frame = serial_frame_ns(9600);
  std::vector<serial_byte> sent;
  for (int i = 0; i < 8; ++i) sent.push_back(byte_at(kStart_ns + (i + 1) * frame, 9600, static_cast<uint8_t>('0' + i)));
  const int64_t change_ns = kStart_ns + 4 * frame;  // the fifth frame's start edge
  SerialWire wire(false);
  wire.set_receiver_baud(9600, 0);
  wire.set_receiver_baud(19200, change_ns);
  for (const serial_byte& b : sent) wire.send(b);
  const std::vector<serial_byte> got = receive_all(wire, kStart_ns + 20 * frame);

  SerialWire after(false);
  const std::vector<serial_byte> expected_after =
      read_through(after, 19200, std::vector<serial_byte>(sent.begin() + 4, sent.end()), kStart_ns + 20 * frame);
  ASSERT_GE(expected_after.size(), 4u);  // each 9600 frame read at twice the rate gives one or two bytes
  ASSERT_EQ(got.size(), 4 + expected_after.size());
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(got[i].value, sent[i].value) << i;
    EXPECT_EQ(got[i].end_ns, sent[i].end_ns) << i;
  }
  for (size_t i = 0; i < expected_after.size(); ++i) {
    EXPECT_EQ(got[4 + i].value, expected_after[i].value) << i;
    EXPECT_EQ(got[4 + i].end_ns, expected_after[i].end_ns) << i;
    EXPECT_EQ(got[4 + i].baud, 19200u) << i;
  }
}

// '0' (0x30: data 0 0 0 0 1 1 0 0) sent at 9600, read at 4800. Receiver bits are 2 T; samples
// at (2k + 1.06) T from the start edge, so it reads every other sender bit:
//   k:           0   1   2   3   4    5 .. 8 | 9 (stop)
//   sender bit:  d0  d2  d4  d6  stop idle   | idle
//   level:       0   0   1   0   1    1      | 1     -> data 0b11111010 = 0xFA, stop fine
// ending 20 T after the start. And '5' (data 1 0 1 0 1 1 0 0) at 4800: the start edges at 0, 2 T
// and 4 T are each rejected as spikes (the mid-start samples at 1.06, 3.06, 5.06 T land on d0,
// d2, d4, all 1); the edge at 7 T (d6) passes (8.06 T is d7 = 0) and everything after is the
// idle line: 0xFF, ending at 27 T.
TEST(SerialWire, NineSixHundredReadAtFortyEightHundredGivesThePredictedGarbage) {
  {
    SerialWire wire(false);
    const std::vector<serial_byte> got = read_9600_byte(wire, 4800, '0', kStart_ns + 60 * 104167);
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].value, 0xFA);
    EXPECT_EQ(got[0].end_ns, kStart_ns + serial_frame_ns(4800));
    EXPECT_EQ(wire.framing_errors(), 0u);
  }
  {
    SerialWire wire(false);
    const std::vector<serial_byte> got = read_9600_byte(wire, 4800, '5', kStart_ns + 60 * 104167);
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].value, 0xFF);
    EXPECT_EQ(got[0].end_ns, bit_time(kStart_ns, 7, 9600) + serial_frame_ns(4800));
  }
}

// "R123\r" as a MaxBotix TX sends it: back to back at 9600, RS-232 polarity (idle low, every bit
// inverted). Line levels by bit position p from the 'R' frame's start (S = inverted start = 1,
// inverted stop = 0):
//   'R' 0x52  p0-9:   1 | 1 0 1 1 0 1 0 1 | 0
//   '1' 0x31  p10-19: 1 | 0 1 1 1 0 0 1 1 | 0
//   '2' 0x32  p20-29: 1 | 1 0 1 1 0 0 1 1 | 0
//   '3' 0x33  p30-39: 1 | 0 0 1 1 0 0 1 1 | 0
//   CR  0x0D  p40-49: 1 | 0 1 0 0 1 1 1 1 | 0      then idle 0
// A normal receiver at 9600 needs a high-to-low edge: first at p2. Start p2, data p3-p10 =
// 1 1 0 1 0 1 0 1 -> 0xAB, stop p11 = 0: framing error. Hunting from p11.6: next fall p15;
// data p16-23 = 0 1 1 0 1 1 0 1 -> 0xB6, stop p24 = 1. Next fall p25; data p26-33 =
// 0 1 1 0 1 0 0 1 -> 0x96, stop p34 = 1. Next fall p35; data p36-43 = 0 1 1 0 1 0 1 0 -> 0x56
// 'V', stop p44 = 0: framing error. The line rises at p45 and falls at p49 (the CR's stop):
// data p50-57 idle 0 -> 0x00, stop p58 = 0: framing error; the line then stays low, so nothing
// more. Each byte ends 10 bits after its start edge: at p12, p25, p35, p45, p59.
TEST(SerialWire, InvertedMaxbotixTextReadsAsThePredictedGarbageAndTheInverterRestoresIt) {
  const uint32_t baud = MAXBOTIX_BAUD;
  uint8_t text[5];
  ASSERT_EQ(maxbotix_serial_frame(123, text), 5u);
  const int64_t start = 2000000;
  const int64_t frame = serial_frame_ns(baud);
  std::vector<serial_byte> sent;
  for (int i = 0; i < 5; ++i) sent.push_back(byte_at(start + (i + 1) * frame, baud, text[i]));

  SerialWire inverted(MAXBOTIX_SERIAL_INVERTED != 0);
  const std::vector<serial_byte> got = read_through(inverted, baud, sent, start + 80 * 104167);
  const uint8_t expected[] = {0xAB, 0xB6, 0x96, 0x56, 0x00};
  // Start edges at p2, p15, p25, p35, p49: bit p % 10 of the frame sent (p / 10)-th.
  const int start_bits[] = {2, 15, 25, 35, 49};
  ASSERT_EQ(got.size(), 5u);
  std::string as_text;
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(got[i].value, expected[i]) << i;
    const int p = start_bits[i];
    EXPECT_EQ(got[i].end_ns, bit_time(start + (p / 10) * frame, p % 10, baud) + frame) << i;
    as_text.push_back(static_cast<char>(got[i].value));
  }
  EXPECT_EQ(as_text.find("R1"), std::string::npos);
  EXPECT_EQ(as_text.find('\r'), std::string::npos);
  EXPECT_EQ(inverted.framing_errors(), 3u);

  // The wiring's inverter (a MAX232 or a transistor) undoes the polarity: the text comes through.
  SerialWire through_inverter(false);
  const std::vector<serial_byte> clean = read_through(through_inverter, baud, sent, start + 80 * 104167);
  ASSERT_EQ(clean.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(clean[i].value, text[i]);
    EXPECT_EQ(clean[i].end_ns, sent[i].end_ns);
  }
}

// Decoding in 1 ms batches gives exactly what decoding the whole stream at once gives: bytes
// that straddle a batch wait for the line they need. Also: a port not begun gets nothing, and
// one begun mid-stream picks up from its next start edge.
TEST(SerialWire, BatchesDecodeLikeOneStreamAndAPortNotBegunGetsNothing) {
  const uint32_t baud = 9600;
  const int64_t frame = serial_frame_ns(baud);
  std::vector<serial_byte> sent;
  for (int k = 0; k < 20; ++k) {  // 20 MaxBotix frames, 49 ms apart
    uint8_t text[5];
    maxbotix_serial_frame(6 + 12 * k, text);
    for (int i = 0; i < 5; ++i) sent.push_back(byte_at(3000000 + k * 49000000 + (i + 1) * frame, baud, text[i]));
  }
  const int64_t last = sent.back().end_ns + 10 * frame;
  for (const uint32_t rx_baud : {4800u, 9600u, 19200u, 38400u}) {
    SerialWire whole(true), batched(true);
    const std::vector<serial_byte> once = read_through(whole, rx_baud, sent, last + 1000000);
    batched.set_receiver_baud(rx_baud, 0);
    std::vector<serial_byte> in_batches;
    size_t next = 0;
    for (int64_t q_end = 1000000; q_end <= last + 1000000; q_end += 1000000) {
      while (next < sent.size() && sent[next].end_ns < q_end) batched.send(sent[next++]);
      batched.receive_until(q_end, in_batches);
    }
    ASSERT_EQ(once.size(), in_batches.size()) << rx_baud;
    EXPECT_FALSE(once.empty()) << rx_baud;
    for (size_t i = 0; i < once.size(); ++i) {
      EXPECT_EQ(once[i].value, in_batches[i].value) << rx_baud << " " << i;
      EXPECT_EQ(once[i].end_ns, in_batches[i].end_ns) << rx_baud << " " << i;
    }
  }

  SerialWire idle_port(false);
  for (const serial_byte& b : sent) idle_port.send(b);
  EXPECT_TRUE(receive_all(idle_port, last + 1000000).empty());  // never begun: baud 0

  // Begun at 9600 in the middle of frame 10's 'R': what is left of that burst may read as
  // garbage (a receiver starting mid-frame takes a data edge for a start bit), but after the
  // idle gap before frame 11 every byte is exact.
  SerialWire late(false);
  const int64_t begin_ns = sent[50].end_ns - frame / 2;
  late.set_receiver_baud(0, 0);
  late.set_receiver_baud(baud, begin_ns);
  for (const serial_byte& b : sent) late.send(b);
  const std::vector<serial_byte> got = receive_all(late, last + 1000000);
  ASSERT_GE(got.size(), 45u);
  EXPECT_LE(got.size(), 50u);  // at most one byte per start edge in what is left of frame 10
  EXPECT_GT(got.front().end_ns, begin_ns);
  for (size_t i = 0; i < 45; ++i) {
    const serial_byte& g = got[got.size() - 45 + i];
    EXPECT_EQ(g.value, sent[55 + i].value) << i;
    EXPECT_EQ(g.end_ns, sent[55 + i].end_ns) << i;
  }
}

// A sender that changes rate mid-stream, as an LMS2xx does after `20 42`: an 8-byte burst at
// `from`, both ends switch to `to` where its last stop bit ends, and after `gap_ns` another burst at
// `to`. The sender gives each byte only once its stop bit has ended (the devices' transmit
// contract), quantum by quantum, and announces its rate as the bridge does; the receiver's rate
// change is known before the wire is read past it.
struct RateChange {
  uint32_t from, to, rx_after;  // rx_after: the receiver's rate from the switch on
  int64_t gap_ns, quantum_ns;
};

std::vector<serial_byte> two_bursts(const RateChange& c, int64_t* switch_ns) {
  std::vector<serial_byte> sent;
  int64_t end = 3000000 + 123457;  // an odd phase against every quantum below
  for (int i = 0; i < 8; ++i) sent.push_back(byte_at(end += serial_frame_ns(c.from), c.from, static_cast<uint8_t>(0x06 + 0x31 * i)));
  *switch_ns = end;
  end += c.gap_ns;
  // 06 02 first, as the reply that lost them; then values with every bit pattern kind.
  const uint8_t second[8] = {0x06, 0x02, 0x80, 0x03, 0x00, 0xFF, 0x55, 0xAA};
  for (uint8_t v : second) sent.push_back(byte_at(end += serial_frame_ns(c.to), c.to, v));
  return sent;
}

std::vector<serial_byte> stream_through(const RateChange& c, const std::vector<serial_byte>& sent, int64_t switch_ns,
                                        uint64_t* framing_errors) {
  SerialWire wire(false);
  wire.set_receiver_baud(c.from, 0);
  wire.set_sender_baud(c.from, 0);
  std::vector<serial_byte> got;
  size_t next = 0;
  bool switched = false;
  const int64_t last = sent.back().end_ns + 4 * serial_frame_ns(std::min(c.to, c.rx_after)) + 2 * c.quantum_ns;
  for (int64_t q_end = c.quantum_ns; q_end <= last; q_end += c.quantum_ns) {
    while (next < sent.size() && sent[next].end_ns < q_end) wire.send(sent[next++]);
    if (!switched && switch_ns < q_end) {
      wire.set_sender_baud(c.to, switch_ns);
      wire.set_receiver_baud(c.rx_after, switch_ns);
      switched = true;
    }
    const size_t before = got.size();
    wire.receive_until(q_end, got);
    for (size_t i = before; i < got.size(); ++i) EXPECT_LT(got[i].end_ns, q_end);
  }
  *framing_errors = wire.framing_errors();
  return got;
}

// The same line read with all of it known at once: what a receiver at those rates decodes.
std::vector<serial_byte> read_whole(const RateChange& c, const std::vector<serial_byte>& sent, int64_t switch_ns) {
  SerialWire wire(false);
  wire.set_receiver_baud(c.from, 0);
  wire.set_receiver_baud(c.rx_after, switch_ns);
  for (const serial_byte& b : sent) wire.send(b);
  return receive_all(wire, sent.back().end_ns + 40 * serial_frame_ns(std::min(c.to, c.rx_after)));
}

constexpr uint32_t kLmsRates[] = {9600, 19200, 38400, 500000};

// Both ends change rate together, each way between the LMS2xx's four rates: every byte of both
// bursts comes through byte-exact, at its own time, whatever the frame length against the
// quantum (a 9600 frame is 1.04 ms, longer than the 1 ms and 0.25 ms quanta) and wherever the
// second burst starts in a quantum. Before the fix a burst after a change to a slower rate lost
// its first frames: the wire judged the line known up to one frame at the old, faster rate before
// the quantum's end, and hunted past the start bit of a slow frame not yet sent.
TEST(SerialWire, RateChangesBothWaysPassBytesThroughExactly) {
  for (uint32_t from : kLmsRates)
    for (uint32_t to : kLmsRates) {
      if (from == to) continue;
      for (int64_t quantum : {INT64_C(250000), INT64_C(1000000), INT64_C(5000000)})
        for (int64_t gap : {INT64_C(0), INT64_C(1000000), INT64_C(2000000) + 777, INT64_C(6100003)}) {
          const RateChange c{from, to, to, gap, quantum};
          int64_t switch_ns = 0;
          const std::vector<serial_byte> sent = two_bursts(c, &switch_ns);
          uint64_t framing = 0;
          const std::vector<serial_byte> got = stream_through(c, sent, switch_ns, &framing);
          const std::string where = std::to_string(from) + "->" + std::to_string(to) + " q " + std::to_string(quantum) +
                                    " gap " + std::to_string(gap);
          ASSERT_EQ(got.size(), sent.size()) << where;
          for (size_t i = 0; i < sent.size(); ++i) {
            EXPECT_EQ(got[i].value, sent[i].value) << where << " byte " << i;
            EXPECT_EQ(got[i].end_ns, sent[i].end_ns) << where << " byte " << i;
            EXPECT_EQ(got[i].baud, sent[i].baud) << where << " byte " << i;
          }
          EXPECT_EQ(framing, 0u) << where;
        }
    }
}

// When the ends disagree after the change (the receiver stays, or takes a third rate), the
// quantum-by-quantum reading still gives exactly what the whole line gives a real receiver:
// garbage, but the same garbage at the same times, for every pair of rates and every quantum.
TEST(SerialWire, MismatchedRateChangesDecodeLikeTheWholeLine) {
  for (uint32_t from : kLmsRates)
    for (uint32_t to : kLmsRates)
      for (uint32_t rx : kLmsRates) {
        if (from == to || rx == to) continue;
        for (int64_t quantum : {INT64_C(250000), INT64_C(1000000)}) {
          const RateChange c{from, to, rx, INT64_C(1500000), quantum};
          int64_t switch_ns = 0;
          const std::vector<serial_byte> sent = two_bursts(c, &switch_ns);
          uint64_t framing = 0;
          const std::vector<serial_byte> got = stream_through(c, sent, switch_ns, &framing);
          const std::vector<serial_byte> whole = read_whole(c, sent, switch_ns);
          const std::string where = std::to_string(from) + "->" + std::to_string(to) + " rx " + std::to_string(rx) +
                                    " q " + std::to_string(quantum);
          ASSERT_EQ(got.size(), whole.size()) << where;
          ASSERT_GE(got.size(), 8u) << where;  // the first burst, at least, is read
          for (size_t i = 0; i < whole.size(); ++i) {
            EXPECT_EQ(got[i].value, whole[i].value) << where << " byte " << i;
            EXPECT_EQ(got[i].end_ns, whole[i].end_ns) << where << " byte " << i;
          }
        }
      }
}

}  // namespace
