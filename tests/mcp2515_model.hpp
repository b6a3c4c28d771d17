// An MCP2515 written from its datasheet (Microchip DS20001801) for the host test of the AVR CAN
// driver: the SPI instruction set, the register file with its read-only and config-only bits,
// the modes, acceptance, BUKT rollover, overflow flags, transmit priority and the INT pin.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace sear::test {

struct ModelFrame {
  uint32_t id = 0;
  bool extended = false;
  bool remote = false;
  uint8_t dlc = 0;
  std::array<uint8_t, 8> data{};
  bool operator==(const ModelFrame& o) const {
    return id == o.id && extended == o.extended && remote == o.remote && dlc == o.dlc &&
           (remote || std::equal(data.begin(), data.begin() + dlc, o.data.begin()));
  }
};

class Mcp2515Model {
 public:
  Mcp2515Model() { reset(); }

  // The SPI side: chip select and one byte each way.
  void select(bool low);
  uint8_t transfer(uint8_t mosi);
  bool selected() const { return cs_low_; }

  // The bus side. deliver() is a frame received off the bus (acceptance, BUKT, overflow);
  // send_next() puts the pending buffer the controller would pick on the bus and acknowledges it.
  void deliver(const ModelFrame& frame);
  std::optional<ModelFrame> send_next();

  bool int_low() const { return (reg_[kCanIntE] & reg_[kCanIntF]) != 0; }
  uint8_t mode() const { return reg_[kCanStat] & 0xE0; }
  uint8_t reg(uint8_t address) const { return reg_[address]; }
  void poke(uint8_t address, uint8_t value) { reg_[address] = value; }  // error counters, EFLG
  // The bit rate CNF1..3 give with this crystal, 0 when they break section 5.3's rules.
  double bitrate(double osc_hz) const;
  int overflows() const { return overflows_; }
  // Writes into a transmit buffer while it was pending, which section 3.3 forbids.
  int pending_writes() const { return pending_writes_; }

  static constexpr uint8_t kCanStat = 0x0E, kCanCtrl = 0x0F, kCnf3 = 0x28, kCnf2 = 0x29, kCnf1 = 0x2A,
                           kCanIntE = 0x2B, kCanIntF = 0x2C, kEflg = 0x2D, kRxb0Ctrl = 0x60, kRxb1Ctrl = 0x70;

 private:
  void reset();
  void write(uint8_t address, uint8_t value, uint8_t mask);
  void end_instruction();
  void update_mode();
  bool accepts(const ModelFrame& frame, int filter, int mask) const;
  void store(int buffer, const ModelFrame& frame, int filter);

  std::array<uint8_t, 128> reg_{};
  bool cs_low_ = false;
  std::vector<uint8_t> bytes_;  // of the instruction under way
  uint8_t address_ = 0;
  int read_rx_ = -1;  // READ RX BUFFER under way: clears RXnIF when CS rises
  int overflows_ = 0;
  int pending_writes_ = 0;
};

// A transmit buffer's SIDH, SIDL, EID8, EID0, DLC, D0..D7 as the frame they put on the bus.
ModelFrame decode_tx_buffer(const uint8_t* sidh);

}  // namespace sear::test
