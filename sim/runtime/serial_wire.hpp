// One serial line between a UART sender and a UART receiver that may disagree on the baud rate
// or the polarity: turns the sender's frames into the bytes an AVR-style receiver decodes.
#pragma once

#include <cstdint>
#include <vector>

#include "devices/serial_byte.h"

namespace sear {

// Sender frames are 8N1 at the baud each serial_byte carries. With `inverted`, the line carries
// them in RS-232 polarity at logic levels (idle low, every bit inverted), as a MaxBotix TX pin
// does; the receiver always expects normal TTL polarity (idle high, start bit low).
//
// The receiver follows the ATmega2560 datasheet, USART "Asynchronous Data Reception": a start bit
// needs a high-to-low transition while idle; it is confirmed by sampling mid start bit (the
// middle of the three majority samples 8-10 of 16) and rejected as a spike if high; each data bit
// and the stop bit are sampled mid-bit; a low stop bit is a framing error, but the byte still
// reaches the data register, so it is delivered. After the stop bit's samples the receiver hunts
// for the next high-to-low transition (a line that stays low after a framing error gives
// nothing until it has been high again). The 16x sample clock's phase against the line is unknown
// on a real board; we take its mean (the edge seen 1/32 bit late), so samples never fall exactly
// on a sender's bit boundary when the rates are in simple ratios. A byte is stamped with the end
// of its stop bit counted from the true edge, so equal rates give the sender's own times.
//
// Streaming contract: send() frames in time order; receive_until(until) assumes every frame that
// ends before `until` has been sent. A frame still on the line at `until` is unknown: it started
// no earlier than one of its own frames before `until`, so the line is known up to
// max(last frame end, until - one frame at the slowest rate the sender may have used since).
// A decoded byte whose samples reach past that waits for the next call and keeps its own
// (earlier) time. The sender's rate is what set_sender_baud announced; without announcements,
// the rate of its last frame (which is wrong right after it changed to a slower rate: its next,
// longer frame may have started before the horizon that rate gives).
class SerialWire {
 public:
  explicit SerialWire(bool inverted);

  void send(const serial_byte& byte);
  // From from_ns on the receiver runs at `baud`; 0 means the port is not begun (decodes
  // nothing). Changes come in time order, before receive_until passes their time; a frame is
  // read at the baud in force when its start edge is seen.
  void set_receiver_baud(uint32_t baud, int64_t from_ns);
  // From from_ns on the sender sends at `baud` (0: it sends nothing). Changes come in time
  // order, before receive_until passes their time.
  void set_sender_baud(uint32_t baud, int64_t from_ns);
  // Appends the decoded bytes whose stop bit ends before until_ns, stamped with that end as the
  // receiver sees it and carrying the receiver's baud.
  void receive_until(int64_t until_ns, std::vector<serial_byte>& out);

  // Framing errors seen so far (stop bit sampled low), for diagnostics and tests.
  uint64_t framing_errors() const { return framing_errors_; }

 private:
  struct Frame {
    int64_t start_ns;
    int64_t end_ns;
    uint32_t baud;
    uint8_t value;
  };
  struct BaudChange {
    int64_t from_ns;
    uint32_t baud;
  };
  // A frame's offsets from its start edge at one rate: its stop bit's start, its end, and where
  // the receiver hunts again.
  struct FrameTimes {
    uint32_t baud;
    int64_t stop_bit_ns;
    int64_t frame_ns;
    int64_t hunt_again_ns;
  };

  static void set_baud(std::vector<BaudChange>& list, uint32_t baud, int64_t from_ns);
  uint32_t baud_at(int64_t t_ns) const;
  // When the receiver's rate in force at t_ns next changes (INT64_MAX: never, so far).
  int64_t receiver_baud_until(int64_t t_ns) const;
  const FrameTimes& times(uint32_t baud) const;  // of the last rate asked for, kept
  // Up to where the line is known when every frame ending before until_ns has been sent.
  int64_t known_until(int64_t until_ns) const;
  int level_at(int64_t t_ns) const;
  // First high-to-low transition at or after from_ns and before limit_ns, or INT64_MAX.
  int64_t next_falling_edge(int64_t from_ns, int64_t limit_ns) const;
  // Decodes what the known line allows into ready_, advancing scan_from_ns_.
  void decode(int64_t known_until_ns);
  void forget_before(int64_t t_ns);

  bool inverted_;
  std::vector<Frame> frames_;
  std::vector<BaudChange> bauds_;         // the receiver's
  std::vector<BaudChange> sender_bauds_;  // the sender's, as announced; the first still in force at last_end_ns_ on
  std::vector<serial_byte> ready_;  // decoded, waiting for their end to pass
  int64_t scan_from_ns_ = INT64_MIN;  // where the receiver starts hunting for a start edge
  int64_t last_end_ns_ = INT64_MIN;
  uint32_t last_sender_baud_ = 0;
  uint64_t framing_errors_ = 0;
  mutable FrameTimes times_{0, 0, 0, 0};
};

}  // namespace sear
