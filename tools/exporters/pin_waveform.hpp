// One MCU's pins and ports as VCD waveforms (IEEE 1364 section 18), in two files. The pins, as a
// logic analyser shows them: each pin's level, whether the firmware drives it or a device does
// (an echo, an encoder, a data-ready line, a switch), a USART's TX and RX pins carrying their frames
// (start bit, eight data bits from the least significant, stop bit), one-bit wires only, so that
// sigrok (PulseView, sigrok-cli), whose VCD reader stops at the first multi-bit value, reads them
// with its protocol decoders. The values, for GTKWave: each PWM pin's duty, each servo pin's pulse
// width and each UART line's bytes. A VCD declares every variable before its first value, and
// which pins a firmware drives is known only as it runs, so every pin and port the board has is
// declared up front.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "exporters/bounded_file.hpp"
#include "lockstep_link.h"

namespace sear {

class PinWaveform {
 public:
  // The ATmega2560 board's pins with a timer output compare (PWM), and those on a 16-bit timer
  // (servo pulses): hal/runtime/board.c refuses the rest, and waveform_test checks the two agree.
  static bool has_pwm(int pin);
  static bool has_servo(int pin);
  // Its USARTs' pins (the Arduino Mega 2560's pinout): TXn and RXn of port n.
  static int uart_tx_pin(int port);
  static int uart_rx_pin(int port);
  // Not a link event: a USART's line level on its pin (index = pin, value = 0/1), for the frames
  // McuCapture lays out from each byte, so that a logic analyser's UART decoder reads the pins.
  static constexpr std::uint8_t kLineLevel = 0xF0;

  // Writes the headers to `pins` and `values`, with every pin an input ('z') and nothing on any
  // port at #0. Without `uart_bytes` the ports' bytes are left out of the values, and the header
  // says where they are: a port streaming at 500 kbaud adds about 0.6 MB a simulated second.
  // `labels` (exporters/pin_labels.hpp), one a pin or none, name what is wired to each pin:
  // pin 22 is "D22_sonar.trig" where "D22" alone would say nothing, and a value on it is named
  // after it ("D5_pwm_left.pwm", "uart1_tx_gps.rx").
  // `uart_frames`: the caller hands it each UART byte's frame as kLineLevel changes. Without them a
  // begun USART's pins show 'x', unknown, rather than an idle line that would hide the traffic,
  // and the header's comment says how to have them drawn.
  PinWaveform(BoundedFile& pins, BoundedFile& values, const std::string& mcu_id, bool uart_bytes = true,
              const std::vector<std::string>& labels = {}, bool uart_frames = true);

  // A batch of the MCU's events, in time order with those before, written at once; the kinds
  // the waveform does not show (CAN) are ignored.
  void write(const sear_event* events, std::size_t count);
  void write(const sear_event& e) { write(&e, 1); }
  // The run or the MCU stopped at end_ns: writes the ends of bytes due by then (see below).
  void finish(std::int64_t end_ns);

 private:
  // A byte's value shows from the end of its stop bit for nine bit times and then returns to 'z',
  // so that two equal bytes back to back (one frame, ten bits, apart) stay apart by a bit of 'z'.
  // Two different bytes back to back need no 'z' between them, and a port streaming at its baud
  // would double the file with it: that end is left out when the line's next byte, different and
  // back to back, is in the same batch; otherwise it waits for the next change or finish(), and
  // is left out if that change is such a byte. So during a run the file may lack a last byte's
  // end until something else changes.
  static constexpr int kByteBits = 9;
  static constexpr int kPorts = SEAR_LINK_UARTS;
  struct Line {
    std::string id;
    int value = -1;            // shown, or last shown
    std::int64_t bit_ns = 0;   // of the shown byte
    std::int64_t end_ns = -1;  // when the shown byte returns to 'z'; -1: none pending
  };

  // One of the two files, with the changes of one event gathered to be written at once.
  struct Stream {
    explicit Stream(BoundedFile& f) : file(f) {}
    BoundedFile& file;
    std::int64_t last_ns = 0;  // the header's values are at #0
    std::int64_t ms = 0;       // last_ns's whole milliseconds, in decimal in ms_text (0: none yet)
    char ms_text[20] = {};     // INT64_MAX / 10^6 has 13 digits
    std::size_t ms_len = 0;
    char text[512];
    std::size_t text_len = 0;
  };
  void stamp(Stream& stream, std::int64_t time_ns);
  void level(std::int64_t time_ns, int pin, char value);
  void show_input(std::int64_t time_ns, int pin);
  void vector(std::int64_t time_ns, const std::string& id, int value);  // value < 0: 'z'
  void show(std::int64_t time_ns, int& shown, const std::string& id, int value);  // if it changed
  void write_one(const sear_event& e);
  static bool joins(const Line& line, std::int64_t time_ns, int value);  // back to back, different
  bool joined_ahead(const Line& line) const;
  void byte(std::int64_t time_ns, int port, bool tx, std::uint8_t value);
  void end_bytes(std::int64_t until_ns);
  // The first n bytes of `line` to the stream's text. The whole array is copied, a size the
  // compiler knows, which is cheaper than a call to copy just n: a 500 kbaud line makes two of
  // these a microsecond.
  template <std::size_t N>
  static void put(Stream& stream, const char (&line)[N], std::size_t n) {
    static_assert(N <= sizeof stream.text);
    if (stream.text_len + N > sizeof stream.text) flush_text(stream);
    std::memcpy(stream.text + stream.text_len, line, N);
    stream.text_len += n;
  }
  static void flush_text(Stream& stream);

  Stream pins_, values_;
  bool uart_bytes_;
  bool uart_frames_;
  std::array<std::string, SEAR_LINK_PINS> duty_id_, servo_id_;  // empty: not such a pin
  std::array<int, SEAR_LINK_PINS> duty_{}, servo_{};            // shown; -1: 'z'
  std::array<bool, SEAR_LINK_PINS> pwm_started_{};              // since the pin last became an output
  std::array<std::uint8_t, SEAR_LINK_PINS> mode_{};    // INPUT, OUTPUT or INPUT_PULLUP (hal/gpio.h)
  std::array<std::uint8_t, SEAR_LINK_PINS> driven_{};  // what a device drives: 0, 1, 2 nothing
  // A port's bit time and how long its bytes show (kByteBits), from its baud rate; a byte before
  // its port's baud is known (none on record) shows for a microsecond: 9 Mbaud.
  void set_baud(int port, std::uint32_t baud);
  std::array<std::int64_t, kPorts> port_bit_ns_{}, port_show_ns_{};
  std::array<Line, 2 * kPorts> lines_;  // port n: tx at 2n, rx at 2n + 1
  std::int64_t next_end_ns_ = INT64_MAX;
  const sear_event* ahead_ = nullptr;  // the batch's events not yet written
  const sear_event* ahead_end_ = nullptr;
};

}  // namespace sear
