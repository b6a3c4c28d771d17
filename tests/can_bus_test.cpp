// The simulated CAN bus: frame lengths against an independent bit-string model of ISO 11898-1,
// CRC-15 against its published check value, times on the wire, arbitration, FIFO order, the
// ACK-error counters of a lone node, and determinism however run_until is chunked.
#include "runtime/can_bus.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bitset>
#include <random>
#include <string>
#include <vector>

#include "runtime/can_bits.hpp"

namespace sear {
namespace {

// ---- An independent model: the frame as a string of '0'/'1', CRC by polynomial long division
// ---- (the textbook definition rather than the shift register), stuffing by inserting chars.

std::string field(std::uint32_t value, int width) {
  return std::bitset<32>(value).to_string().substr(static_cast<std::size_t>(32 - width));
}

std::string reference_unstuffed(const CanFrame& f) {
  std::string s = "0";  // SOF
  if (f.extended)
    s += field(f.id >> 18, 11) + "11" + field(f.id & 0x3FFFF, 18) + (f.remote ? "1" : "0") + "00";
  else
    s += field(f.id, 11) + (f.remote ? "1" : "0") + "00";
  s += field(f.dlc, 4);
  if (!f.remote)
    for (int i = 0; i < f.dlc; ++i) s += field(f.data[static_cast<std::size_t>(i)], 8);
  return s;
}

// Remainder of s(x) * x^15 divided by x^15 + x^14 + x^10 + x^8 + x^7 + x^4 + x^3 + 1.
std::string reference_crc(const std::string& bits) {
  const std::string generator = "1100010110011001";
  std::string work = bits + std::string(15, '0');
  for (std::size_t i = 0; i + 15 < work.size(); ++i)
    if (work[i] == '1')
      for (std::size_t j = 0; j < generator.size(); ++j) work[i + j] = work[i + j] == generator[j] ? '0' : '1';
  return work.substr(work.size() - 15);
}

std::string reference_stuffed(const std::string& bits) {
  std::string out;
  for (char c : bits) {
    out += c;
    // The last five sent bits (stuff bits included) equal: send their complement.
    if (out.size() >= 5 && out.compare(out.size() - 5, 5, std::string(5, c)) == 0) out += c == '0' ? '1' : '0';
  }
  return out;
}

int reference_wire_bits(const CanFrame& f) {
  const std::string unstuffed = reference_unstuffed(f);
  return static_cast<int>(reference_stuffed(unstuffed + reference_crc(unstuffed)).size()) + 10;  // + CRC del, ACK, EOF
}

CanFrame std_frame(std::uint32_t id, std::vector<std::uint8_t> data) {
  CanFrame f;
  f.id = id;
  f.dlc = static_cast<std::uint8_t>(data.size());
  for (std::size_t i = 0; i < data.size(); ++i) f.data[i] = data[i];
  return f;
}

CanFrame ext_frame(std::uint32_t id, std::vector<std::uint8_t> data) {
  CanFrame f = std_frame(id, std::move(data));
  f.extended = true;
  return f;
}

CanFrame remote(CanFrame f, std::uint8_t dlc) {
  f.remote = true;
  f.dlc = dlc;
  f.data = {};
  return f;
}

TEST(CanBits, Crc15MatchesTheCatalogueCheckValue) {
  // CRC-15/CAN in Greg Cook's CRC catalogue (width 15, poly 0x4599, init 0, no reflection, no
  // xorout): check = 0x059E over the ASCII bytes "123456789", MSB first.
  std::vector<std::uint8_t> bits;
  for (char c : std::string("123456789"))
    for (int b = 7; b >= 0; --b) bits.push_back(static_cast<std::uint8_t>((c >> b) & 1));
  EXPECT_EQ(can_bits::crc15(bits.data(), static_cast<int>(bits.size())), 0x059E);
  std::string s;
  for (auto b : bits) s += b ? '1' : '0';
  EXPECT_EQ(reference_crc(s), field(0x059E, 15));
}

TEST(CanBits, KnownFrameLengths) {
  // Unstuffed lengths (SOF..EOF): standard 44 + 8n, extended 64 + 8n (ISO 11898-1).
  // ID 0x000 with 8 x 0x00: SOF, ID, RTR, IDE, r0 are 15 dominant bits (3 stuff bits, the last one
  // recessive), DLC 1000 (its 1 extends the stuff bit's run to 2), then 3 + 64 dominant bits: 13
  // stuff bits with 2 bits left over, then the CRC 0x145B = 001010001011011, whose leading 00
  // makes a run of 4: 16 stuff bits, 108 + 16 = 124 bits.
  const CanFrame zeros = std_frame(0x000, {0, 0, 0, 0, 0, 0, 0, 0});
  EXPECT_EQ(can_bits::unstuffed_bits(zeros).crc, 0x145B);
  EXPECT_EQ(can_bits::wire_bits(zeros), 124);
  // No data: 19 + 15 dominant bits (the CRC of all zeros is 0), 34 = 6 * 5 + 4: 6 stuff bits.
  EXPECT_EQ(can_bits::wire_bits(std_frame(0x000, {})), 44 + 6);
  // ID 0x555 with 4 x 0xAA: alternating bits and a CRC without a run of 5: no stuff bit.
  EXPECT_EQ(can_bits::wire_bits(std_frame(0x555, {0xAA, 0xAA, 0xAA, 0xAA})), 44 + 32);
  // A remote frame sends no data field whatever its DLC.
  EXPECT_EQ(can_bits::wire_bits(remote(std_frame(0x123, {}), 5)), 44);
  // Extended ID 0 with 8 x 0x00: 128 unstuffed bits, 19 stuff bits.
  EXPECT_EQ(can_bits::wire_bits(ext_frame(0, {0, 0, 0, 0, 0, 0, 0, 0})), 64 + 64 + 19);
}

TEST(CanBits, AgreesWithTheReferenceModelAndTheWorstCaseBound) {
  std::mt19937 rng(11);
  std::vector<CanFrame> frames = {std_frame(0x7FF, {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF}),
                                  ext_frame(0x1FFFFFFF, {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF}),
                                  std_frame(0x078, {0x78, 0x3C, 0x1E, 0x0F, 0x87, 0xC3, 0xE1, 0xF0})};
  for (int i = 0; i < 3000; ++i) {
    CanFrame f;
    f.extended = (rng() & 1) != 0;
    f.id = static_cast<std::uint32_t>(rng()) & (f.extended ? 0x1FFFFFFFu : 0x7FFu);
    f.dlc = static_cast<std::uint8_t>(rng() % 9);
    // Bytes from a few values so that long runs of equal bits are common.
    const std::uint8_t pool[] = {0x00, 0xFF, 0x0F, 0xF0, 0x55, 0x83, 0x7C};
    for (int b = 0; b < f.dlc; ++b) f.data[static_cast<std::size_t>(b)] = pool[rng() % 7];
    if (rng() % 8 == 0) f = remote(f, f.dlc);
    frames.push_back(f);
  }
  for (const CanFrame& f : frames) {
    const int n = f.remote ? 0 : f.dlc;
    const int unstuffed = (f.extended ? 64 : 44) + 8 * n;
    const int bits = can_bits::wire_bits(f);
    ASSERT_EQ(bits, reference_wire_bits(f)) << std::hex << f.id << " ext " << f.extended << " dlc " << int(f.dlc);
    // Davis, Burns, Bril, Lukkien (2007): at most floor((g + 8n - 1) / 4) stuff bits, g = 34
    // (standard) or 54 (extended) stuffed bits besides the data.
    const int g = f.extended ? 54 : 34;
    ASSERT_LE(bits - unstuffed, (g + 8 * n - 1) / 4);
  }
}

// ---- The bus

struct Harness {
  CanBus bus;
  std::vector<CanTransfer> done;
  explicit Harness(std::uint32_t rate) : bus(rate) {}
  std::size_t listener() {
    const std::size_t n = bus.add_node("listener");
    bus.set_listening(n, true);
    return n;
  }
};

TEST(CanBus, TimeOnTheWireAtStandardRates) {
  const CanFrame f = std_frame(0x000, {0, 0, 0, 0, 0, 0, 0, 0});  // 124 bits
  for (auto [rate, bit_ns] : {std::pair{125'000u, 8000}, {500'000u, 2000}, {1'000'000u, 1000}}) {
    Harness h(rate);
    const std::size_t a = h.bus.add_node("a");
    h.listener();
    h.bus.request(a, 1000, f, 7);
    h.bus.run_until(1'000'000'000, h.done);
    ASSERT_EQ(h.done.size(), 1u);
    EXPECT_EQ(h.done[0].start_ns, 1000);  // an idle bus: the SOF is the request's time
    EXPECT_EQ(h.done[0].end_ns, 1000 + 124 * bit_ns) << rate;
    EXPECT_TRUE(h.done[0].acked);
    EXPECT_EQ(h.done[0].tag, 7u);
    EXPECT_EQ(h.bus.idle_at_ns(), 1000 + 127 * bit_ns);  // + 3 bits of intermission
  }
}

TEST(CanBus, BackToBackFramesDoNotDriftAtAnInexactRate) {
  // 83 333 bit/s: 12000.48 ns per bit. Frame k of a back-to-back stream starts k * 127 bits
  // after the first; rounding each frame's length to the ns would drift ~0.5 ns per frame.
  Harness h(83'333);
  const std::size_t a = h.bus.add_node("a");
  h.listener();
  const CanFrame f = std_frame(0x000, {0, 0, 0, 0, 0, 0, 0, 0});
  for (int k = 0; k < 1000; ++k) h.bus.request(a, 0, f, static_cast<std::uint64_t>(k));
  h.bus.run_until(3'600'000'000'000, h.done);
  ASSERT_EQ(h.done.size(), 1000u);
  for (int k = 0; k < 1000; k += 111) {
    const long double exact_sof = static_cast<long double>(k) * 127 * 1e9L / 83'333;
    EXPECT_EQ(h.done[static_cast<std::size_t>(k)].start_ns, static_cast<std::int64_t>(exact_sof + 0.5L));
    EXPECT_EQ(h.done[static_cast<std::size_t>(k)].end_ns,
              static_cast<std::int64_t>(exact_sof + 124 * 1e9L / 83'333 + 0.5L));
  }
}

TEST(CanBus, ArbitrationOrdersByTheArbitrationField) {
  struct Case {
    const char* what;
    CanFrame winner, loser;
  };
  const CanFrame ext_base_123 = ext_frame((0x123u << 18) | 0x5, {1});
  const Case cases[] = {
      {"lower standard ID", std_frame(0x0FF, {1}), std_frame(0x100, {1})},
      {"standard data over extended with the same base (RTR vs SRR)", std_frame(0x123, {1}), ext_base_123},
      {"standard remote over extended with the same base (IDE)", remote(std_frame(0x123, {}), 1), ext_base_123},
      {"data over remote, standard", std_frame(0x123, {1}), remote(std_frame(0x123, {}), 1)},
      {"data over remote, extended", ext_frame(0x1234567, {1}), remote(ext_frame(0x1234567, {}), 1)},
      {"lower extended ID-B", ext_frame(0x1234566, {1}), ext_frame(0x1234567, {1})},
      {"lower base ID beats a standard frame", ext_frame(0x122u << 18, {1}), std_frame(0x123, {1})},
  };
  for (const Case& c : cases) {
    for (bool winner_first : {true, false}) {  // node order must not matter
      Harness h(500'000);
      const std::size_t a = h.bus.add_node("a"), b = h.bus.add_node("b");
      h.listener();
      h.bus.request(a, 100, winner_first ? c.winner : c.loser, 1);
      h.bus.request(b, 100, winner_first ? c.loser : c.winner, 2);
      h.bus.run_until(10'000'000, h.done);
      ASSERT_EQ(h.done.size(), 2u);
      EXPECT_EQ(h.done[0].frame, c.winner) << c.what;
      EXPECT_EQ(h.done[0].start_ns, 100) << c.what;
      // The loser retries as soon as the bus is free: the winner's end plus intermission.
      EXPECT_EQ(h.done[1].start_ns, h.done[0].end_ns + 3 * 2000) << c.what;
    }
  }
}

TEST(CanBus, ThreeNodesAndARequestDuringAFrame) {
  Harness h(1'000'000);
  const std::size_t a = h.bus.add_node("a"), b = h.bus.add_node("b"), c = h.bus.add_node("c");
  h.listener();
  h.bus.request(a, 0, std_frame(0x300, {1, 2}), 0);
  h.bus.request(b, 10'000, std_frame(0x200, {3}), 0);  // a is mid-frame: both wait
  h.bus.request(c, 20'000, std_frame(0x100, {4}), 0);
  // Decide frame by frame: each SOF is just before each t_end, so later requests are not in the past.
  h.bus.run_until(1, h.done);
  ASSERT_EQ(h.done.size(), 1u);
  h.bus.run_until(h.done[0].end_ns + 3000 + 1, h.done);
  ASSERT_EQ(h.done.size(), 2u);
  h.bus.run_until(h.done[1].end_ns + 3000 + 1, h.done);
  ASSERT_EQ(h.done.size(), 3u);
  EXPECT_EQ(h.done[0].node, a);
  EXPECT_EQ(h.done[1].node, c);  // 0x100 beats 0x200 at the next arbitration
  EXPECT_EQ(h.done[2].node, b);
  EXPECT_EQ(h.done[1].start_ns, h.done[0].end_ns + 3000);
  EXPECT_EQ(h.done[2].start_ns, h.done[1].end_ns + 3000);
  // A request during intermission waits for its end; one after it starts at once.
  h.bus.request(a, h.done[2].end_ns + 1000, std_frame(0x700, {}), 0);
  h.bus.request(b, h.done[2].end_ns + 500'000, std_frame(0x001, {}), 0);
  h.bus.run_until(2'000'000, h.done);
  ASSERT_EQ(h.done.size(), 5u);
  EXPECT_EQ(h.done[3].start_ns, h.done[2].end_ns + 3000);
  EXPECT_EQ(h.done[4].start_ns, h.done[2].end_ns + 500'000);
}

TEST(CanBus, SameArbitrationFieldGoesToTheLowerNodeIndex) {
  Harness h(500'000);
  const std::size_t a = h.bus.add_node("a"), b = h.bus.add_node("b");
  h.listener();
  h.bus.request(b, 0, std_frame(0x123, {2}), 0);
  h.bus.request(a, 0, std_frame(0x123, {1}), 0);
  h.bus.run_until(1'000'000, h.done);
  ASSERT_EQ(h.done.size(), 2u);
  EXPECT_EQ(h.done[0].node, a);
  EXPECT_EQ(h.done[1].node, b);
}

TEST(CanBus, EachNodeSendsItsOwnFramesOldestFirst) {
  Harness h(1'000'000);
  const std::size_t a = h.bus.add_node("a"), b = h.bus.add_node("b");
  h.listener();
  for (std::uint32_t id : {0x300u, 0x100u, 0x200u}) h.bus.request(a, 0, std_frame(id, {}), id);
  h.bus.request(b, 0, std_frame(0x250, {}), 0x250);
  h.bus.run_until(1'000'000, h.done);
  std::vector<std::uint64_t> order;
  for (const auto& t : h.done) order.push_back(t.tag);
  // a offers only its oldest (0x300), which loses to b's 0x250; then a's in its own order.
  EXPECT_EQ(order, (std::vector<std::uint64_t>{0x250, 0x300, 0x100, 0x200}));
}

TEST(CanBus, DecidesEveryFrameStartedBeforeTheHorizonAndRejectsThePast) {
  Harness h(125'000);
  const std::size_t a = h.bus.add_node("a");
  h.listener();
  h.bus.request(a, 5000, std_frame(0x10, {1, 2, 3}), 0);
  h.bus.request(a, 5000, std_frame(0x11, {}), 0);
  h.bus.run_until(5000, h.done);  // SOF at 5000 is not before 5000
  EXPECT_TRUE(h.done.empty());
  h.bus.run_until(5001, h.done);  // started: decided, though it ends ~0.6 ms later
  ASSERT_EQ(h.done.size(), 1u);
  EXPECT_GT(h.done[0].end_ns, 5001);
  EXPECT_THROW(h.bus.request(a, 5000, std_frame(0x12, {}), 0), std::logic_error);
  EXPECT_THROW(h.bus.request(a, 6000, std_frame(0x800, {}), 0), std::invalid_argument);  // 12 bits
}

TEST(CanBus, LoneNodeGoesErrorPassiveAndStaysThere) {
  Harness h(1'000'000);
  const std::size_t a = h.bus.add_node("a");
  h.bus.set_listening(a, true);  // it listens, but a sender never acks itself
  const CanFrame f = std_frame(0x123, {0xDE, 0xAD, 0xBE, 0xEF});
  const int bits = can_bits::wire_bits(f);
  ASSERT_EQ(bits, 78);
  h.bus.request(a, 0, f, 0);
  std::vector<int> tec;
  for (int attempt = 0; attempt < 20; ++attempt) {
    // Nine bit times past the free bus: one attempt's SOF, active (at once) or passive (+8 bits).
    h.bus.run_until(h.bus.idle_at_ns() + 9000, h.done);
    tec.push_back(h.bus.counters(a).tec);
    EXPECT_EQ(h.bus.counters(a).state, attempt < 15 ? CanErrorState::active : CanErrorState::passive);
  }
  EXPECT_EQ(tec,
            (std::vector<int>{8, 16, 24, 32, 40, 48, 56, 64, 72, 80, 88, 96, 104, 112, 120, 128, 128, 128, 128, 128}));
  ASSERT_EQ(h.done.size(), 20u);
  // An attempt: the frame up to its ACK slot (bits - 8), the 6 + 8 bit error frame, 3 bits of
  // intermission; error passive, 8 more bits of suspended transmission.
  for (std::size_t i = 0; i < h.done.size(); ++i) {
    EXPECT_FALSE(h.done[i].acked);
    EXPECT_EQ(h.done[i].end_ns - h.done[i].start_ns, (bits - 8 + 14) * 1000);
    if (i > 0) {
      EXPECT_EQ(h.done[i].start_ns - h.done[i - 1].start_ns, (i <= 15 ? 87 : 95) * 1000) << i;
    }
  }
  // Someone joins: the frame goes through, TEC falls by one and the node is active again.
  const std::size_t b = h.bus.add_node("b");
  h.bus.set_listening(b, true);
  h.bus.run_until(h.bus.idle_at_ns() + 9000, h.done);
  EXPECT_TRUE(h.done.back().acked);
  EXPECT_EQ(h.bus.counters(a).tec, 127);
  EXPECT_EQ(h.bus.counters(a).state, CanErrorState::active);
  EXPECT_EQ(h.bus.counters(b).rec, 0);  // a success lowers REC, never below 0
}

TEST(CanBus, ErrorPassiveSenderSuspendsAfterEveryFrame) {
  Harness h(1'000'000);
  const std::size_t a = h.bus.add_node("a"), b = h.bus.add_node("b");
  const CanFrame f = std_frame(0x123, {0xDE, 0xAD, 0xBE, 0xEF});  // 78 bits
  auto step = [&] { h.bus.run_until(h.bus.idle_at_ns() + 9000, h.done); };
  h.bus.request(a, 0, f, 0);
  for (int i = 0; i < 16; ++i) step();  // alone: TEC 128
  h.bus.set_listening(b, true);
  step();  // acked: 127, error active
  h.bus.set_listening(b, false);
  h.bus.request(a, h.bus.horizon_ns(), f, 0);
  step();  // an ACK error while active: 127 + 8 = 135, error passive
  ASSERT_EQ(h.bus.counters(a).tec, 135);
  h.bus.set_listening(b, true);
  h.bus.request(a, h.bus.horizon_ns(), f, 0);
  h.bus.run_until(h.bus.horizon_ns() + 1'000'000, h.done);
  // The failed frame again, then the new one: two successes, 135 -> 133, error passive throughout,
  // so each waits intermission + 8 bits of suspended transmission after the frame before it.
  EXPECT_EQ(h.bus.counters(a).tec, 133);
  ASSERT_GE(h.done.size(), 3u);
  for (std::size_t i = h.done.size() - 2; i < h.done.size(); ++i) {
    EXPECT_TRUE(h.done[i].acked);
    EXPECT_EQ(h.done[i].start_ns - h.done[i - 1].end_ns, (3 + 8) * 1000);
  }
}

TEST(CanBus, SuccessesLowerTecToZero) {
  Harness h(500'000);
  const std::size_t a = h.bus.add_node("a");
  h.bus.request(a, 0, std_frame(0x1, {}), 0);
  for (int i = 0; i < 3; ++i) h.bus.run_until(h.bus.idle_at_ns() + 1, h.done);
  ASSERT_EQ(h.bus.counters(a).tec, 24);
  h.listener();
  for (int i = 0; i < 30; ++i) h.bus.request(a, h.bus.horizon_ns(), std_frame(0x1, {}), 0);
  h.bus.run_until(h.bus.horizon_ns() + 1'000'000'000, h.done);
  EXPECT_EQ(h.bus.counters(a).tec, 0);  // 24 down by one per success, then held at 0
  EXPECT_EQ(h.bus.pending(a), 0u);
}

bool same(const std::vector<CanTransfer>& x, const std::vector<CanTransfer>& y) {
  if (x.size() != y.size()) return false;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (x[i].start_ns != y[i].start_ns || x[i].end_ns != y[i].end_ns || x[i].node != y[i].node ||
        !(x[i].frame == y[i].frame) || x[i].tag != y[i].tag || x[i].acked != y[i].acked)
      return false;
  return true;
}

std::vector<CanTransfer> lone_node_for_one_second(std::int64_t quantum_ns) {
  Harness h(1'000'000);
  const std::size_t a = h.bus.add_node("a");
  h.bus.request(a, 0, std_frame(0x123, {0xDE, 0xAD, 0xBE, 0xEF}), 0);
  for (std::int64_t t = quantum_ns; t <= 1'000'000'000; t += quantum_ns) h.bus.run_until(t, h.done);
  // Attempts j = 0..15 start 87 bits apart, then 95: those before 1 s number
  // 16 + floor((1e6 - 1 - 15 * 87) / 95) = 16 + 10512.
  const CanCounters c = h.bus.counters(a);
  EXPECT_EQ(h.done.size(), CanBus::kReportedFailures);
  EXPECT_EQ(h.done.size() + c.unreported_failures, 10528u);
  EXPECT_EQ(c.tec, 128);
  EXPECT_EQ(h.bus.idle_at_ns(), (15 * 87 + 10512 * 95 + 87) * 1000);
  return h.done;
}

TEST(CanBus, LoneNodeRetriesCostLittleAndDoNotDependOnTheQuantum) {
  const auto one_call = lone_node_for_one_second(1'000'000'000);
  EXPECT_TRUE(same(lone_node_for_one_second(1'000'000), one_call));
  // And far ahead in one call: an hour of retries, skipped arithmetically.
  Harness h(1'000'000);
  const std::size_t a = h.bus.add_node("a");
  h.bus.request(a, 0, std_frame(0x123, {}), 0);
  h.bus.run_until(3'600'000'000'000, h.done);
  EXPECT_EQ(h.done.size(), CanBus::kReportedFailures);
  EXPECT_GT(h.bus.counters(a).unreported_failures, 30'000'000u);
}

std::vector<CanTransfer> random_traffic(std::int64_t quantum_ns) {
  std::mt19937 rng(2026);
  Harness h(250'000);
  std::vector<std::size_t> nodes;
  for (int i = 0; i < 4; ++i) nodes.push_back(h.bus.add_node("n" + std::to_string(i)));
  h.bus.set_listening(nodes[0], true);
  h.bus.set_listening(nodes[1], true);
  // Requests generated ahead, handed to the bus quantum by quantum as a run would.
  struct Req {
    std::int64_t t;
    std::size_t node;
    CanFrame f;
  };
  std::vector<Req> reqs;
  std::vector<std::int64_t> last(4, 0);
  for (int i = 0; i < 400; ++i) {
    const std::size_t n = rng() % 4;
    last[n] += static_cast<std::int64_t>(rng() % 2'000'000);
    CanFrame f;
    f.extended = (rng() % 3) == 0;
    f.id = static_cast<std::uint32_t>(rng()) & (f.extended ? 0x1FFFFFFFu : 0x7FFu);
    f.dlc = static_cast<std::uint8_t>(rng() % 9);
    for (auto& byte : f.data) byte = static_cast<std::uint8_t>(rng());
    for (int b = f.dlc; b < 8; ++b) f.data[static_cast<std::size_t>(b)] = 0;
    reqs.push_back({last[n], n, f});
  }
  std::stable_sort(reqs.begin(), reqs.end(), [](const Req& x, const Req& y) { return x.t < y.t; });
  std::size_t next = 0;
  for (std::int64_t t = quantum_ns; next < reqs.size() || t < 400'000'000; t += quantum_ns) {
    for (; next < reqs.size() && reqs[next].t < t; ++next)
      h.bus.request(reqs[next].node, reqs[next].t, reqs[next].f, next);
    h.bus.run_until(t, h.done);
  }
  return h.done;
}

TEST(CanBus, DeterministicRuns) {
  const auto a = random_traffic(1'000'000);
  EXPECT_EQ(a.size(), 400u);
  EXPECT_TRUE(same(a, random_traffic(1'000'000)));
  // Requests reach the bus before the quantum that passes their time: the quantum changes nothing.
  EXPECT_TRUE(same(a, random_traffic(100'000)));
  EXPECT_TRUE(same(a, random_traffic(7'777'777)));
  // Frames never overlap on the wire.
  for (std::size_t i = 1; i < a.size(); ++i) ASSERT_GE(a[i].start_ns, a[i - 1].end_ns + 3 * 4000) << i;
}

}  // namespace
}  // namespace sear
