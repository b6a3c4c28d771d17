// The UART logs the capture writes (exporters/mcu_capture): each byte's line stamped with the end
// of its stop bit, in time order across directions, the raw bytes beside them, the console's
// lines, and what a stopped MCU never sent; the same files whether a stream's bytes are written
// in runs (as `sear run` writes them) or one event at a time (as when the waveform shows them).
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "exporters/mcu_capture.hpp"
#include "firmware_run.hpp"

namespace sear::test {
namespace {

namespace fs = std::filesystem;

constexpr std::int64_t kUs = 1000;  // ns
constexpr std::int64_t kFrame500k = 20 * kUs;  // ten bits at 500 kbaud

sear_event event(std::int64_t t, std::uint8_t kind, std::uint8_t index, std::uint32_t value) {
  return {t, value, kind, index, {0, 0}};
}

// A firmware's turn as the link hands it on: its own bytes stamped ahead with the end of their
// stop bits, a stream's bytes back to back across the turn of a second, a reply that ends at the
// same instant as one of them, a console line, and bytes still queued when it stops at
// 1.000 100 s (a byte that arrives after that is not taken).
std::vector<sear_event> turn() {
  std::vector<sear_event> e;
  e.push_back(event(500000 * kUs, SEAR_EVENT_UART_BEGIN, 0, 9600));
  e.push_back(event(500000 * kUs, SEAR_EVENT_UART_BEGIN, 1, 500000));
  const std::string line = "hi\n";
  for (std::size_t k = 0; k < line.size(); ++k)
    e.push_back(event(999000 * kUs + static_cast<std::int64_t>(k + 1) * kUs, SEAR_EVENT_UART_TX, 0,
                      static_cast<std::uint8_t>(line[k])));
  // Nine, the third ending on the second itself and the ninth after the stop.
  const std::int64_t first_end = 999960 * kUs;
  for (int i = 0; i < 9; ++i) {
    // Sent while the third came in, stamped ahead with the end of its stop bit, which is the
    // fourth's: of equal times, the event written first comes first.
    if (i == 3) e.push_back(event(first_end + 3 * kFrame500k, SEAR_EVENT_UART_TX, 1, 0xA5));
    e.push_back(event(first_end + i * kFrame500k, SEAR_EVENT_UART_RX, 1, static_cast<std::uint8_t>(0x30 + i)));
  }
  e.push_back(event(1000130 * kUs, SEAR_EVENT_UART_TX, 1, 0x5A));  // after the stop: never sent
  e.push_back(event(1000120 * kUs, SEAR_EVENT_UART_TX, 0, 'x'));
  return e;
}

void capture_into(const fs::path& dir, bool waveform_bytes) {
  McuCapture::Mcu mcu{"r.m", 0};
  mcu.waveform_uart_bytes = waveform_bytes;
  McuCapture capture(dir.string(), {mcu}, false, UINT64_MAX);
  const std::vector<sear_event> events = turn();
  capture.on_events(0, events.data(), events.size());
  capture.on_stop(0, 1000100 * kUs);
  capture.advance_to(999970 * kUs);  // a step's end inside the stream: it goes on in the next
  capture.advance_to(1001000 * kUs);
  capture.finish(1002000 * kUs);
}

TEST(UartLog, AStreamsBytesAreStampedInTimeOrderAcrossTheTurnOfASecond) {
  TempDir dir;
  capture_into(dir.path(), false);
  const std::string log = read_file(dir.path() / "r.m.uart1.log");
  // Each stamp is the end of the byte's stop bit to the nanosecond, 20 us (ten bits at 500 kbaud)
  // apart; the seconds' digits turn with the third; the lines keep the order of their times.
  EXPECT_EQ(log,
            "# SEAR UART capture: mcu r.m, port 1, 8N1\n"
            "# time_s (end of the stop bit), direction (tx, rx, or baud when the port starts), byte in hex\n"
            "0.500000000 baud 500000\n"
            "0.999960000 rx 30\n"
            "0.999980000 rx 31\n"
            "1.000000000 rx 32\n"
            "1.000020000 tx a5\n"
            "1.000020000 rx 33\n"
            "1.000040000 rx 34\n"
            "1.000060000 rx 35\n"
            "1.000080000 rx 36\n"
            "1.000100000 rx 37\n"
            "# 1.000100000: 1 bytes queued never sent: the MCU stopped\n");
  EXPECT_EQ(read_file(dir.path() / "r.m.uart1.rx.bin"), "01234567");
  EXPECT_EQ(read_file(dir.path() / "r.m.uart1.tx.bin"), "\xA5");
  EXPECT_EQ(read_file(dir.path() / "r.m.console.log"), "0.999003000 hi\n1.000100000 [never sent] x\n");
}

TEST(UartLog, BytesWrittenInRunsMakeTheSameFilesAsBytesWrittenOneAtATime) {
  TempDir runs, one_at_a_time;
  capture_into(runs.path(), false);
  capture_into(one_at_a_time.path(), true);  // every byte queued for the waveform, event by event
  for (const char* name : {"r.m.uart0.log", "r.m.uart0.tx.bin", "r.m.uart1.log", "r.m.uart1.rx.bin",
                           "r.m.uart1.tx.bin", "r.m.console.log"}) {
    ASSERT_TRUE(fs::exists(runs.path() / name)) << name;
    EXPECT_EQ(read_file(runs.path() / name), read_file(one_at_a_time.path() / name)) << name;
  }
}

}  // namespace
}  // namespace sear::test
