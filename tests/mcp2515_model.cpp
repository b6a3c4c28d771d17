// The MCP2515 model of mcp2515_model.hpp; section numbers are those of DS20001801.
#include "mcp2515_model.hpp"

namespace sear::test {
namespace {

constexpr uint8_t kTxbCtrl[3] = {0x30, 0x40, 0x50};
constexpr uint8_t kRxfSidh[6] = {0x00, 0x04, 0x08, 0x10, 0x14, 0x18};
constexpr uint8_t kRxmSidh[2] = {0x20, 0x24};

bool in_range(uint8_t a, uint8_t lo, uint8_t hi) { return a >= lo && a <= hi; }

// Table 11-1 marks the registers BIT MODIFY works on; on the others the mask counts as 0xFF.
bool bit_modifiable(uint8_t a) {
  return a == 0x0C || a == 0x0D || a == 0x0F || in_range(a, 0x28, 0x2D) || a == 0x30 || a == 0x40 ||
         a == 0x50 || a == 0x60 || a == 0x70;
}

uint32_t field_sid(const uint8_t* r) { return (uint32_t(r[0]) << 3) | (r[1] >> 5); }
uint32_t field_eid(const uint8_t* r) { return (uint32_t(r[1] & 3u) << 16) | (uint32_t(r[2]) << 8) | r[3]; }

}  // namespace

ModelFrame decode_tx_buffer(const uint8_t* b) {
  ModelFrame f;
  f.extended = (b[1] & 0x08) != 0;  // EXIDE
  f.id = f.extended ? (field_sid(b) << 18) | field_eid(b) : field_sid(b);
  f.remote = (b[4] & 0x40) != 0;  // TXBnDLC.RTR, for both kinds (register 3-7)
  f.dlc = b[4] & 0x0F;
  for (int i = 0; i < 8; i++) f.data[i] = b[5 + i];
  return f;
}

void Mcp2515Model::reset() {
  // Section 9 and table 11-2: control registers to their reset values; buffers, filters and
  // masks are undefined ('x'), shown here as a pattern no driver should rely on.
  reg_.fill(0xA5);
  for (int a : {0x0C, 0x0D, 0x1C, 0x1D, 0x28, 0x29, 0x2A, 0x2B, 0x2C, 0x2D, 0x30, 0x40, 0x50, 0x60, 0x70})
    reg_[a] = 0;
  reg_[kCanStat] = 0x80;  // configuration mode
  reg_[kCanCtrl] = 0x87;  // REQOP = configuration, CLKEN, CLKPRE = /8
}

void Mcp2515Model::update_mode() {
  uint8_t& ctrl = reg_[kCanCtrl];
  if (ctrl & 0x10) {  // ABAT: every pending transmission aborted (section 3.4)
    for (uint8_t c : kTxbCtrl)
      if (reg_[c] & 0x08) reg_[c] = uint8_t((reg_[c] & ~0x08) | 0x40);  // TXREQ off, ABTF on
  }
  const uint8_t requested = ctrl & 0xE0;
  bool pending = false;
  for (uint8_t c : kTxbCtrl) pending |= (reg_[c] & 0x08) != 0;
  // Section 10: the mode changes only once pending transmissions are complete.
  if (requested == 0x80 && pending && mode() != 0x80) return;
  reg_[kCanStat] = uint8_t((reg_[kCanStat] & 0x1F) | requested);
}

void Mcp2515Model::write(uint8_t a, uint8_t value, uint8_t mask) {
  a &= 0x7F;
  const bool config = mode() == 0x80;
  uint8_t writable = 0xFF;
  if ((a & 0x0F) == 0x0E || a == 0x1C || a == 0x1D) writable = 0;  // CANSTAT (and mirrors), TEC, REC
  // Filters, masks and CNF1..3 only in configuration mode (sections 4.5 and 5).
  else if (in_range(a, 0x00, 0x0B) || in_range(a, 0x10, 0x1B) || in_range(a, 0x20, 0x2A)) writable = config ? 0xFF : 0;
  else if (a == 0x2D) writable = 0xC0;  // EFLG: only RX1OVR, RX0OVR
  else if (a == 0x30 || a == 0x40 || a == 0x50) writable = 0x0B;  // TXREQ, TXP
  else if (a == 0x60) writable = 0x64;  // RXM, BUKT
  else if (a == 0x70) writable = 0x60;  // RXM
  else if (a >= 0x61 && (a & 0x0F) != 0 && a <= 0x7D) writable = 0;  // receive buffers
  for (int n = 0; n < 3; n++) {
    if (a > kTxbCtrl[n] && a <= kTxbCtrl[n] + 13 && (reg_[kTxbCtrl[n]] & 0x08)) pending_writes_++;
  }
  const uint8_t m = mask & writable;
  reg_[a] = uint8_t((reg_[a] & ~m) | (value & m));
  if (a == kCanCtrl) update_mode();
}

void Mcp2515Model::select(bool low) {
  if (cs_low_ && !low) end_instruction();
  if (low && !cs_low_) {
    bytes_.clear();
    read_rx_ = -1;
  }
  cs_low_ = low;
}

void Mcp2515Model::end_instruction() {
  // Section 12.4: READ RX BUFFER clears the buffer's RXnIF when CS rises.
  if (read_rx_ >= 0) reg_[kCanIntF] = uint8_t(reg_[kCanIntF] & ~(1u << read_rx_));
  read_rx_ = -1;
}

uint8_t Mcp2515Model::transfer(uint8_t mosi) {
  if (!cs_low_) return 0xFF;  // MISO stays high-impedance; the bus pulls it high
  bytes_.push_back(mosi);
  const uint8_t op = bytes_[0];
  const size_t i = bytes_.size() - 1;  // index of this byte in the instruction
  if (i == 0) {
    if (op == 0xC0) reset();
    if ((op & 0xF9) == 0x90) {  // READ RX BUFFER 1001 0nm0
      const int n = (op >> 2) & 1;
      address_ = uint8_t((n ? 0x71 : 0x61) + ((op & 0x02) ? 5 : 0));
      read_rx_ = n;
    }
    if ((op & 0xF8) == 0x40) {  // LOAD TX BUFFER 0100 0abc
      const int n = (op >> 1) & 3;
      address_ = uint8_t(kTxbCtrl[n] + ((op & 1) ? 6 : 1));
    }
    if ((op & 0xF8) == 0x80) {  // RTS 1000 0nnn
      for (int n = 0; n < 3; n++)
        if (op & (1 << n)) reg_[kTxbCtrl[n]] |= 0x08;
    }
    return 0xFF;
  }
  switch (op) {
    case 0x03:  // READ
      if (i == 1) {
        address_ = mosi & 0x7F;
        return 0xFF;
      }
      return reg_[address_++ & 0x7F];
    case 0x02:  // WRITE
      if (i == 1) {
        address_ = mosi & 0x7F;
        return 0xFF;
      }
      write(address_++, mosi, 0xFF);
      return 0xFF;
    case 0x05:  // BIT MODIFY: address, mask, data
      if (i == 3) write(bytes_[1], mosi, bit_modifiable(bytes_[1] & 0x7F) ? bytes_[2] : 0xFF);
      return 0xFF;
    case 0xA0: {  // READ STATUS (figure 12-8), repeated while clocked
      uint8_t s = reg_[kCanIntF] & 0x03;
      for (int n = 0; n < 3; n++) {
        if (reg_[kTxbCtrl[n]] & 0x08) s |= uint8_t(0x04 << (2 * n));
        if (reg_[kCanIntF] & (0x04 << n)) s |= uint8_t(0x08 << (2 * n));
      }
      return s;
    }
    default:
      if ((op & 0xF9) == 0x90) return reg_[address_++];
      if ((op & 0xF8) == 0x40) {
        write(address_++, mosi, 0xFF);
        return 0xFF;
      }
      return 0xFF;
  }
}

bool Mcp2515Model::accepts(const ModelFrame& f, int filter, int mask) const {
  const uint8_t* rf = &reg_[kRxfSidh[filter]];
  const uint8_t* rm = &reg_[kRxmSidh[mask]];
  if (((rf[1] & 0x08) != 0) != f.extended) return false;  // EXIDE picks the kind (section 4.5)
  const uint32_t sid = f.extended ? f.id >> 18 : f.id;
  if ((sid ^ field_sid(rf)) & field_sid(rm) & 0x7FF) return false;
  if (f.extended) return ((f.id & 0x3FFFF) ^ field_eid(rf)) & field_eid(rm) & 0x3FFFF ? false : true;
  // A standard frame: EID15..0 of mask and filter are compared with data bytes 0 and 1.
  const uint32_t bytes = (uint32_t(f.data[0]) << 8) | f.data[1];
  return ((bytes ^ field_eid(rf)) & field_eid(rm) & 0xFFFF) == 0;
}

void Mcp2515Model::store(int n, const ModelFrame& f, int filter) {
  uint8_t* b = &reg_[n ? 0x71 : 0x61];
  if (f.extended) {
    b[0] = uint8_t(f.id >> 21);
    b[1] = uint8_t((((f.id >> 18) & 7) << 5) | 0x08 | ((f.id >> 16) & 3));
    b[2] = uint8_t(f.id >> 8);
    b[3] = uint8_t(f.id);
    b[4] = uint8_t(f.dlc | (f.remote ? 0x40 : 0));  // RXBnDLC.RTR: extended frames only
  } else {
    b[0] = uint8_t(f.id >> 3);
    b[1] = uint8_t(((f.id & 7) << 5) | (f.remote ? 0x10 : 0));  // SRR: a standard remote frame
    b[2] = b[3] = 0;
    b[4] = f.dlc;
  }
  if (!f.remote)
    for (int i = 0; i < f.dlc && i < 8; i++) b[5 + i] = f.data[i];
  uint8_t& ctrl = reg_[n ? kRxb1Ctrl : kRxb0Ctrl];
  const uint8_t filhit = n ? uint8_t(filter & 7) : uint8_t(filter & 1);
  ctrl = uint8_t((ctrl & (n ? 0x60 : 0x64)) | (f.remote ? 0x08 : 0) | filhit);
  reg_[kCanIntF] |= uint8_t(1u << n);
}

void Mcp2515Model::deliver(const ModelFrame& f) {
  if (mode() != 0x00) return;  // only normal mode takes part in the bus here
  const uint8_t ctrl0 = reg_[kRxb0Ctrl], ctrl1 = reg_[kRxb1Ctrl];
  int hit0 = -1, hit1 = -1;
  if ((ctrl0 & 0x60) == 0x60) hit0 = 0;  // RXM = 11: every frame
  else
    for (int k = 0; k < 2 && hit0 < 0; k++)
      if (accepts(f, k, 0)) hit0 = k;
  if ((ctrl1 & 0x60) == 0x60) hit1 = 2;
  else
    for (int k = 2; k < 6 && hit1 < 0; k++)
      if (accepts(f, k, 1)) hit1 = k;
  const bool full0 = reg_[kCanIntF] & 1, full1 = reg_[kCanIntF] & 2;
  // Figure 4-2: RXB0 first; with BUKT a frame for a full RXB0 rolls over into RXB1.
  if (hit0 >= 0) {
    if (!full0) return store(0, f, hit0);
    if (ctrl0 & 0x04) {
      if (!full1) return store(1, f, hit0);
      reg_[kEflg] |= 0x80;  // RX1OVR
    } else {
      reg_[kEflg] |= 0x40;  // RX0OVR
    }
    overflows_++;
    return;
  }
  if (hit1 >= 0) {
    if (!full1) return store(1, f, hit1);
    reg_[kEflg] |= 0x80;
    overflows_++;
  }
}

std::optional<ModelFrame> Mcp2515Model::send_next() {
  if (mode() != 0x00) return std::nullopt;
  // Section 3.2: the highest TXP first, the highest buffer number among equals.
  int pick = -1;
  for (int n = 0; n < 3; n++) {
    const uint8_t c = reg_[kTxbCtrl[n]];
    if (!(c & 0x08)) continue;
    if (pick < 0 || (c & 3) >= (reg_[kTxbCtrl[pick]] & 3)) pick = n;
  }
  if (pick < 0) return std::nullopt;
  const ModelFrame f = decode_tx_buffer(&reg_[kTxbCtrl[pick] + 1]);
  reg_[kTxbCtrl[pick]] &= uint8_t(~0x08);
  reg_[kCanIntF] |= uint8_t(0x04 << pick);  // TXnIF
  update_mode();
  return f;
}

double Mcp2515Model::bitrate(double osc_hz) const {
  const int brp = reg_[kCnf1] & 0x3F, sjw = (reg_[kCnf1] >> 6) + 1;
  const int prseg = (reg_[kCnf2] & 7) + 1, ps1 = ((reg_[kCnf2] >> 3) & 7) + 1;
  // BTLMODE = 0 takes PS2 as the larger of PS1 and the 2-quantum processing time.
  const int ps2 = (reg_[kCnf2] & 0x80) ? (reg_[kCnf3] & 7) + 1 : std::max(ps1, 2);
  const int quanta = 1 + prseg + ps1 + ps2;
  // Section 5.3: PRSEG + PS1 >= PS2, PS2 > SJW, PS2 >= 2 (IPT), 8..25 quanta a bit.
  if (prseg + ps1 < ps2 || ps2 <= sjw || ps2 < 2 || quanta < 8 || quanta > 25) return 0;
  return osc_hz / (2.0 * (brp + 1)) / quanta;
}

}  // namespace sear::test
