// The AVR target's CAN driver (hal/targets/avr/can.c) compiled for the host and run against an
// MCP2515 register model (mcp2515_model.cpp): this file provides the few HAL calls the driver
// makes (spi_*, digital_write, pin_mode, irq_*, micros, delay_us), so no HAL runtime is linked.
// Expected bytes come from the register layouts of the datasheet, Microchip DS20001801.
#include <gtest/gtest.h>

#include <hal/can.h>
#include <hal/gpio.h>
#include <hal/irq.h>

#include <vector>

#include "mcp2515.h"
#include "mcp2515_model.hpp"

namespace {

using sear::test::Mcp2515Model;
using sear::test::ModelFrame;

constexpr uint8_t kCsPin = 10;  // the CAN-BUS shield on a Mega: CS on D10, INT on D2
constexpr uint8_t kIntPin = 2;

// The board around the chip: the chip-select wire, the INT wire into an edge interrupt, the
// global interrupt switch, and a microsecond clock that moves with every call.
struct Board {
  Mcp2515Model chip;
  bool irq_off = false, in_isr = false;
  irq_handler int_handler = nullptr;
  uint8_t int_pin = 0xFF, int_edge = 0;
  bool int_was_low = false, edge_pending = false;
  uint32_t us = 0;
  int unguarded_transfers = 0;  // SPI bytes the receive interrupt could have cut into
  int spi_mode = -1;
  uint32_t spi_hz = 0;
  uint8_t pin_modes[HAL_PIN_COUNT] = {};
  bool no_chip = false;

  void watch_int() {
    const bool low = chip.int_low();
    if (low && !int_was_low && int_handler && int_edge == IRQ_FALLING) edge_pending = true;
    int_was_low = low;
  }
  // An AVR takes a latched edge as soon as interrupts are on and none is running.
  void dispatch() {
    while (edge_pending && !irq_off && !in_isr) {
      edge_pending = false;
      in_isr = true;
      int_handler();
      in_isr = false;
    }
  }
};

Board board;

}  // namespace

extern "C" {
void spi_begin(uint8_t mode, uint32_t clock_hz) {
  board.spi_mode = mode;
  board.spi_hz = clock_hz;
}
uint8_t spi_transfer(uint8_t out) {
  if (!board.irq_off && !board.in_isr) board.unguarded_transfers++;
  board.us += 1;  // 8 bits at 8 MHz, rounded up
  return board.no_chip ? 0xFF : board.chip.transfer(out);
}
void digital_write(uint8_t pin, uint8_t level) {
  if (pin != kCsPin) return;
  board.chip.select(level == LOW);
  board.watch_int();
}
void pin_mode(uint8_t pin, uint8_t mode) { board.pin_modes[pin] = mode; }
void irq_attach_pin(uint8_t pin, uint8_t edge, irq_handler handler) {
  board.int_pin = pin;
  board.int_edge = edge;
  board.int_handler = handler;
  board.int_was_low = board.chip.int_low();
  board.edge_pending = false;  // attaching clears the flag, as EIFR is on the AVR
}
void irq_detach_pin(uint8_t) { board.int_handler = nullptr; }
void irq_disable(void) { board.irq_off = true; }
void irq_enable(void) {
  board.irq_off = false;
  board.dispatch();
}
uint32_t micros(void) { return board.us += 4; }
void delay_us(uint32_t us) { board.us += us; }
}

namespace {

ModelFrame frame(uint32_t id, bool extended, bool remote, std::vector<uint8_t> data, uint8_t dlc = 0xFF) {
  ModelFrame f;
  f.id = id;
  f.extended = extended;
  f.remote = remote;
  f.dlc = dlc == 0xFF ? uint8_t(data.size()) : dlc;
  for (size_t i = 0; i < data.size(); i++) f.data[i] = data[i];
  return f;
}

can_frame to_hal(const ModelFrame& m) {
  can_frame f{};
  f.id = m.id;
  f.extended = m.extended;
  f.remote = m.remote;
  f.dlc = m.dlc;
  for (int i = 0; i < 8; i++) f.data[i] = m.data[i];
  return f;
}

ModelFrame from_hal(const can_frame& f) {
  ModelFrame m;
  m.id = f.id;
  m.extended = f.extended;
  m.remote = f.remote;
  m.dlc = f.dlc;
  for (int i = 0; i < 8; i++) m.data[i] = f.data[i];
  return m;
}

void deliver(const ModelFrame& f) {
  board.chip.deliver(f);
  board.watch_int();
  board.dispatch();
}

ModelFrame receive() {
  can_frame f{};
  EXPECT_EQ(can_receive(&f), 1);
  return from_hal(f);
}

std::vector<int> pending_buffers() {
  std::vector<int> out;
  for (int n = 0; n < 3; n++)
    if (board.chip.reg(uint8_t(0x30 + 0x10 * n)) & 0x08) out.push_back(n);
  return out;
}

// One bit's quanta and sample point as the datasheet's figure 5-1 adds them up from CNF1..3.
struct Timing {
  unsigned brp, quanta, ps2, sjw;
};
Timing timing(const uint8_t cnf[3]) {
  const unsigned prseg = (cnf[1] & 7u) + 1, ps1 = ((cnf[1] >> 3) & 7u) + 1, ps2 = (cnf[2] & 7u) + 1;
  return {(cnf[0] & 0x3Fu) + 1, 1 + prseg + ps1 + ps2, ps2, (cnf[0] >> 6) + 1u};
}

// Exactly the rate: Fosc / (2 (BRP + 1) N) with no remainder; sample point 75..87.5 % (CiA 301
// recommends 87.5 % up to 500 kbit/s and 75 % at 1 Mbit/s); SJW 1; the model's section 5.3 rules.
void expect_exact(double osc_hz, uint32_t rate, const uint8_t cnf[3]) {
  SCOPED_TRACE(testing::Message() << rate << " bit/s from " << osc_hz / 1e6 << " MHz");
  const Timing t = timing(cnf);
  const uint64_t divider = 2ull * t.brp * t.quanta;
  EXPECT_EQ(uint64_t(osc_hz) % divider, 0u);
  EXPECT_EQ(uint64_t(osc_hz) / divider, rate);
  const double sample = double(t.quanta - t.ps2) / t.quanta;
  EXPECT_GE(sample, 0.75);
  EXPECT_LE(sample, 0.875);
  EXPECT_EQ(t.sjw, 1u);
  EXPECT_TRUE(cnf[1] & 0x80) << "BTLMODE: PHSEG2 from CNF3";
  Mcp2515Model chip;  // the chip's own view: zero when a rule of section 5.3 is broken
  chip.select(true);
  for (uint8_t b : {uint8_t(0x02), uint8_t(0x28), cnf[2], cnf[1], cnf[0]}) chip.transfer(b);
  chip.select(false);
  EXPECT_EQ(chip.bitrate(osc_hz), double(rate));
}

constexpr uint32_t kRates[] = {10000, 20000, 50000, 100000, 125000, 250000, 500000, 1000000};

class Mcp2515Driver : public testing::Test {
 protected:
  void SetUp() override {
    board = Board{};
    can_attach_rx(nullptr);
    ASSERT_EQ(can_begin(500000), 0);
  }
  void TearDown() override {
    can_attach_rx(nullptr);
    EXPECT_EQ(board.unguarded_transfers, 0) << "SPI outside a critical section";
    EXPECT_EQ(board.chip.pending_writes(), 0) << "a pending transmit buffer was written";
    EXPECT_EQ(board.spi_mode, 0);
    EXPECT_LE(board.spi_hz, 10000000u) << "the MCP2515's SPI limit";
  }
};

TEST(Mcp2515Timing, EveryRateExactFromBothCrystals) {
  for (double osc : {16e6, 8e6}) {
    for (uint32_t rate : kRates) {
      uint8_t cnf[3];
      const int8_t ok = mcp2515_bit_timing(uint32_t(osc), rate, cnf);
      // At least 8 quanta of 2 / Fosc a bit: 1 Mbit/s needs Fosc >= 16 MHz.
      if (osc == 8e6 && rate == 1000000) {
        EXPECT_EQ(ok, -1);
        continue;
      }
      ASSERT_EQ(ok, 0) << rate;
      expect_exact(osc, rate, cnf);
    }
  }
  uint8_t cnf[3];
  EXPECT_EQ(mcp2515_bit_timing(16000000, 83333, cnf), -1) << "8e6 / 83333 is no whole number of quanta";
  // 500 kbit/s at 16 MHz: 16 quanta of 125 ns, PHSEG2 = 2, sample point 14/16 = 87.5 %.
  ASSERT_EQ(mcp2515_bit_timing(16000000, 500000, cnf), 0);
  EXPECT_EQ(timing(cnf).brp, 1u);
  EXPECT_EQ(timing(cnf).quanta, 16u);
  EXPECT_EQ(timing(cnf).ps2, 2u);
}

TEST_F(Mcp2515Driver, BeginProgramsTheRateOrRefuses) {
  for (uint32_t rate : kRates) {
    ASSERT_EQ(can_begin(rate), 0);
    const uint8_t cnf[3] = {board.chip.reg(0x2A), board.chip.reg(0x29), board.chip.reg(0x28)};
    expect_exact(16e6, rate, cnf);
    EXPECT_EQ(board.chip.mode(), 0x00) << "normal mode";
    // Accept everything after can_begin: RXM = 11 in both, and RXB0 rolls over into RXB1.
    EXPECT_EQ(board.chip.reg(0x60) & 0x64, 0x64);
    EXPECT_EQ(board.chip.reg(0x70) & 0x60, 0x60);
  }
  EXPECT_EQ(board.pin_modes[kCsPin], OUTPUT);
  EXPECT_EQ(can_begin(40000), -1) << "not a rate can.h lists";
  EXPECT_EQ(can_begin(83333), -1);
  // No shield: MISO floats high and every READ answers 0xFF, OPMOD 111, never configuration.
  board.no_chip = true;
  EXPECT_EQ(can_begin(500000), -1);
  board.no_chip = false;
}

TEST_F(Mcp2515Driver, TransmitBuffersHoldTheDatasheetLayout) {
  // Standard 0x123: SID10..3 = 0x24 in SIDH, SID2..0 = 011 in SIDL bits 7..5, EXIDE = 0.
  const ModelFrame standard = frame(0x123, false, false, {0xDE, 0xAD, 0xBE});
  can_frame out = to_hal(standard);
  ASSERT_EQ(can_send(&out), 0);
  std::vector<int> pending = pending_buffers();
  ASSERT_EQ(pending.size(), 1u);
  uint8_t base = uint8_t(0x31 + 0x10 * pending[0]);
  EXPECT_EQ(board.chip.reg(base + 0), 0x24);
  EXPECT_EQ(board.chip.reg(base + 1), 0x60);
  EXPECT_EQ(board.chip.reg(base + 4), 0x03) << "DLC 3, RTR 0";
  EXPECT_EQ(board.chip.reg(base + 5), 0xDE);
  EXPECT_EQ(board.chip.reg(base + 6), 0xAD);
  EXPECT_EQ(board.chip.reg(base + 7), 0xBE);
  auto sent = board.chip.send_next();
  ASSERT_TRUE(sent);
  EXPECT_EQ(*sent, standard);

  // Extended 0x18DAF110 remote with DLC 2: SID = id bits 28..18 = 0x636 -> SIDH 0xC6,
  // SIDL = 110 << 5 | EXIDE | EID17..16 = 10 -> 0xCA; EID8 0xF1, EID0 0x10; DLC = RTR | 2.
  const ModelFrame extended = frame(0x18DAF110, true, true, {}, 2);
  out = to_hal(extended);
  ASSERT_EQ(can_send(&out), 0);
  pending = pending_buffers();
  ASSERT_EQ(pending.size(), 1u);
  base = uint8_t(0x31 + 0x10 * pending[0]);
  EXPECT_EQ(board.chip.reg(base + 0), 0xC6);
  EXPECT_EQ(board.chip.reg(base + 1), 0xCA);
  EXPECT_EQ(board.chip.reg(base + 2), 0xF1);
  EXPECT_EQ(board.chip.reg(base + 3), 0x10);
  EXPECT_EQ(board.chip.reg(base + 4), 0x42);
  sent = board.chip.send_next();
  ASSERT_TRUE(sent);
  EXPECT_EQ(*sent, extended);
}

TEST_F(Mcp2515Driver, FramesLeaveOldestFirst) {
  // Three queued, the fourth refused, and the controller's own priority rule sends them in order.
  for (uint32_t id = 1; id <= 3; id++) {
    can_frame f = to_hal(frame(id, false, false, {uint8_t(id)}));
    ASSERT_EQ(can_send(&f), 0);
  }
  EXPECT_EQ(can_tx_pending(), 3);
  can_frame extra = to_hal(frame(4, false, false, {}));
  EXPECT_EQ(can_send(&extra), -1);
  for (uint32_t id = 1; id <= 3; id++) EXPECT_EQ(board.chip.send_next()->id, id);
  EXPECT_EQ(can_tx_pending(), 0);

  // A long stream where the bus takes a frame now and then: always in order, and a buffer left
  // free is refused only when the keys (3 TXP + n, 12 of them) below the newest pending frame
  // have run out. Keys only fall while the queue holds a frame, and a search over every order of
  // sends and completions finds 12 acceptances from an empty queue before the first refusal; a
  // refusal lasts until the queue is empty again.
  uint32_t next_id = 100, expect_id = 100;
  int accepted = 0, stalls = 0;
  bool stalled = false;
  for (int step = 0; step < 600; step++) {
    if (step % 7 == 3 || step % 5 == 1) {
      if (auto f = board.chip.send_next()) {
        EXPECT_EQ(f->id, expect_id++);
      }
      continue;
    }
    can_frame f = to_hal(frame(next_id, false, false, {uint8_t(next_id)}));
    if (can_send(&f) == 0) {
      next_id++;
      accepted++;
      stalled = false;
    } else if (pending_buffers().size() < 3 && !stalled) {
      stalls++;
      stalled = true;
    }
  }
  while (auto f = board.chip.send_next()) {
    EXPECT_EQ(f->id, expect_id++);
  }
  EXPECT_EQ(expect_id, next_id);
  EXPECT_GT(accepted, 100);
  EXPECT_GT(stalls, 0) << "the stream should outrun the bus";
  EXPECT_LE(stalls * 12, accepted);
}

TEST_F(Mcp2515Driver, FiltersAndMasksLandInTheirRegisters) {
  can_set_mask(0, 0x7FF);
  can_set_filter(0, 0x120, 0);
  can_set_filter(1, 0x300, 0);
  can_set_mask(1, 0x1FFFFF00);
  for (uint8_t f = 2; f < CAN_FILTERS; f++) can_set_filter(f, 0x18DAF100, 1);
  EXPECT_EQ(board.chip.mode(), 0x00) << "back in normal mode";
  // RXF0: 0x120 -> SIDH 0x24, SIDL 000 << 5, EXIDE 0. RXF1: 0x300 -> 0x60, 0x00.
  EXPECT_EQ(board.chip.reg(0x00), 0x24);
  EXPECT_EQ(board.chip.reg(0x01), 0x00);
  EXPECT_EQ(board.chip.reg(0x04), 0x60);
  EXPECT_EQ(board.chip.reg(0x05), 0x00);
  // RXF2..5 at 08h, 10h, 14h, 18h: 0x18DAF100 with EXIDE.
  for (uint8_t a : {uint8_t(0x08), uint8_t(0x10), uint8_t(0x14), uint8_t(0x18)}) {
    EXPECT_EQ(board.chip.reg(a + 0), 0xC6);
    EXPECT_EQ(board.chip.reg(a + 1), 0xCA);
    EXPECT_EQ(board.chip.reg(a + 2), 0xF1);
    EXPECT_EQ(board.chip.reg(a + 3), 0x00);
  }
  // RXM0 over standard filters: SID10..0 all ones, EID15..0 zero (data bytes not compared).
  EXPECT_EQ(board.chip.reg(0x20), 0xFF);
  EXPECT_EQ(board.chip.reg(0x21), 0xE0);
  EXPECT_EQ(board.chip.reg(0x22), 0x00);
  EXPECT_EQ(board.chip.reg(0x23), 0x00);
  // RXM1 = 0x1FFFFF00 laid out as a 29-bit identifier.
  EXPECT_EQ(board.chip.reg(0x24), 0xFF);
  EXPECT_EQ(board.chip.reg(0x25), 0xE3);
  EXPECT_EQ(board.chip.reg(0x26), 0xFF);
  EXPECT_EQ(board.chip.reg(0x27), 0x00);
  EXPECT_EQ(board.chip.reg(0x60) & 0x64, 0x04) << "RXB0: filters on, BUKT";
  EXPECT_EQ(board.chip.reg(0x70) & 0x60, 0x00) << "RXB1: filters on";

  deliver(frame(0x120, false, false, {1, 2}));     // kept by filter 0
  deliver(frame(0x121, false, false, {}));         // no filter
  deliver(frame(0x120, true, false, {}));          // extended, and filters 0-1 are standard
  EXPECT_EQ(can_available(), 1);
  EXPECT_EQ(receive().id, 0x120u);
  // Filters 2-5 put a frame straight into RXB1, so which of two full buffers is older is known
  // only to a driver that looked in between (the controller keeps no arrival order): here the
  // main loop polls after each frame, as the receive interrupt would.
  deliver(frame(0x18DAF1AB, true, false, {7}));    // kept: mask 1 ignores the low byte
  EXPECT_EQ(can_available(), 1);
  deliver(frame(0x18DAF200, true, false, {}));     // no filter
  deliver(frame(0x300, false, true, {}, 1));       // kept by filter 1
  EXPECT_EQ(can_available(), 2);
  EXPECT_EQ(receive(), frame(0x18DAF1AB, true, false, {7}));
  EXPECT_EQ(receive(), frame(0x300, false, true, {}, 1));
  EXPECT_EQ(can_available(), 0);
}

TEST_F(Mcp2515Driver, FiltersChangeEvenWithAFrameNobodyAcknowledges) {
  // Configuration mode waits for pending frames (section 10); a lone node's never go, so the
  // driver aborts them (ABAT) after the time three frames would take, rather than hang.
  can_frame f = to_hal(frame(0x55, false, false, {1}));
  ASSERT_EQ(can_send(&f), 0);
  const uint32_t before = board.us;
  can_set_filter(0, 0x55, 0);
  EXPECT_GE(board.us - before, 3u * 160u * 2u) << "waited three 160-bit frames at 2 us a bit first";
  EXPECT_EQ(board.chip.reg(0x00), 0x0A);  // 0x55 >> 3
  EXPECT_EQ(board.chip.reg(0x01), 0xA0);  // 101 << 5
  EXPECT_EQ(board.chip.mode(), 0x00);
  EXPECT_EQ(board.chip.reg(Mcp2515Model::kCanCtrl) & 0x10, 0) << "ABAT released again";
  EXPECT_EQ(can_tx_pending(), 0);
  ASSERT_EQ(can_send(&f), 0) << "and sending works after";
  EXPECT_EQ(board.chip.send_next()->id, 0x55u);
}

TEST_F(Mcp2515Driver, ReceivedFramesDecodeOldestFirst) {
  const ModelFrame frames[] = {frame(0x7FF, false, false, {1, 2, 3, 4, 5, 6, 7, 8}), frame(0x001, false, true, {}, 4),
                               frame(0x1FFFFFFF, true, false, {}), frame(0x00000001, true, true, {}, 8)};
  for (const ModelFrame& f : frames) {
    deliver(f);
    EXPECT_EQ(can_available(), 1);
    EXPECT_EQ(receive(), f);
  }
  can_frame none;
  EXPECT_EQ(can_receive(&none), 0);

  // A to RXB0, B rolls over to RXB1; after A is read C takes RXB0, yet B is older.
  const ModelFrame a = frame(0x10, false, false, {0xA}), b = frame(0x11, false, false, {0xB}),
                   c = frame(0x12, false, false, {0xC}), d = frame(0x13, false, false, {0xD});
  deliver(a);
  deliver(b);
  EXPECT_EQ(can_available(), 2);
  EXPECT_EQ(receive(), a);
  deliver(c);
  EXPECT_EQ(receive(), b);
  deliver(d);  // into RXB1, behind C
  EXPECT_EQ(receive(), c);
  EXPECT_EQ(receive(), d);
}

TEST_F(Mcp2515Driver, OverrunsAndErrorStateFromEflg) {
  deliver(frame(1, false, false, {}));
  deliver(frame(2, false, false, {}));
  deliver(frame(3, false, false, {}));  // both full: lost, RX1OVR
  EXPECT_EQ(board.chip.overflows(), 1);
  can_counters c{};
  can_get_counters(&c);
  EXPECT_EQ(c.rx_overruns, 1);
  EXPECT_EQ(board.chip.reg(Mcp2515Model::kEflg) & 0xC0, 0) << "counted and cleared";
  can_get_counters(&c);
  EXPECT_EQ(c.rx_overruns, 1) << "one flag counts once";

  // Noticed on the read that frees a buffer too: the frame lost while both were full.
  EXPECT_EQ(receive().id, 1u);
  deliver(frame(4, false, false, {}));
  deliver(frame(5, false, false, {}));  // lost
  EXPECT_EQ(receive().id, 2u);
  EXPECT_EQ(board.chip.reg(Mcp2515Model::kEflg) & 0xC0, 0);
  EXPECT_EQ(receive().id, 4u);
  can_get_counters(&c);
  EXPECT_EQ(c.rx_overruns, 2);

  // ISO 11898-1 states: error passive from 128 (TXEP/RXEP), bus-off past 255 (TXBO).
  board.chip.poke(0x1C, 144);
  board.chip.poke(0x1D, 5);
  board.chip.poke(Mcp2515Model::kEflg, 0x10);
  can_get_counters(&c);
  EXPECT_EQ(c.tec, 144);
  EXPECT_EQ(c.rec, 5);
  EXPECT_EQ(c.state, CAN_ERROR_PASSIVE);
  board.chip.poke(Mcp2515Model::kEflg, 0x20 | 0x10);
  can_get_counters(&c);
  EXPECT_EQ(c.state, CAN_BUS_OFF);
  board.chip.poke(Mcp2515Model::kEflg, 0x01);  // EWARN only
  can_get_counters(&c);
  EXPECT_EQ(c.state, CAN_ERROR_ACTIVE);
}

std::vector<ModelFrame> handled;
int handler_calls = 0;
void read_in_handler() {
  handler_calls++;
  can_frame f{};
  if (can_receive(&f) == 1) handled.push_back(from_hal(f));
}
void count_only() { handler_calls++; }

TEST_F(Mcp2515Driver, ReceiveInterruptRunsOncePerKeptFrame) {
  handled.clear();
  handler_calls = 0;
  can_attach_rx(read_in_handler);
  EXPECT_EQ(board.int_pin, kIntPin);
  EXPECT_EQ(board.int_edge, IRQ_FALLING);
  can_set_mask(0, 0x7FF);
  can_set_mask(1, 0x7FF);
  can_set_filter(0, 0x42, 0);  // every other filter stays 0x000, which no frame here uses
  for (uint8_t i = 0; i < 5; i++) deliver(frame(0x42, false, false, {i}));
  deliver(frame(0x43, false, false, {}));  // filtered out: no interrupt
  EXPECT_EQ(handler_calls, 5);
  ASSERT_EQ(handled.size(), 5u);
  for (uint8_t i = 0; i < 5; i++) EXPECT_EQ(handled[i].data[0], i);

  // A handler that leaves the frames to the main loop is still told of each one once.
  handler_calls = 0;
  can_attach_rx(count_only);
  deliver(frame(0x42, false, false, {1}));
  EXPECT_EQ(handler_calls, 1);
  deliver(frame(0x42, false, false, {2}));
  EXPECT_EQ(handler_calls, 2);
  deliver(frame(0x42, false, false, {3}));  // both full: lost, nothing to tell
  EXPECT_EQ(handler_calls, 2);
  EXPECT_EQ(receive().data[0], 1);
  EXPECT_EQ(receive().data[0], 2);
  deliver(frame(0x42, false, false, {4}));
  EXPECT_EQ(handler_calls, 3);
  EXPECT_EQ(receive().data[0], 4);
  EXPECT_FALSE(board.chip.int_low());
}

}  // namespace
