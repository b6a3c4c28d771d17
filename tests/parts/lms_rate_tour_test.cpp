// The LMS2xx across every change between its rates, in firmware (no pty): after each `20 xx`
// the firmware switches its port and asks for the status at once; every byte it got is checked.
// Issue 21: after `20 42` from 38400 the first reply's `06 02` arrived as one byte 0x90, and from
// 500000 the `06` was lost, because the serial wire judged a slower frame's start already past.
#include <gtest/gtest.h>

#include <cstdint>
#include <regex>
#include <string>
#include <vector>

#include "devices/sick_lms2xx.h"
#include "firmware_run.hpp"

namespace sear::test {
namespace {

std::vector<uint8_t> from_hex(const std::string& hex) {
  std::vector<uint8_t> out;
  for (size_t i = 0; i + 1 < hex.size(); i += 2) out.push_back(static_cast<uint8_t>(std::stoul(hex.substr(i, 2), nullptr, 16)));
  return out;
}

TEST(Lms2xxRateTour, EveryChangeEachWayIsAnsweredAndHeardByteExact) {
  TempDir dir;
  const std::string mcu = std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + LMS_RATE_TOUR +
                          "\"/>\n      <lms2xx name=\"lidar\" uart=\"1\" power_up=\"2\"/>\n    </mcu>\n";
  const SearRun run = run_sear(dir, rover_project(mcu, "", 6.0));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string console = run.file("rover.main.console.log");
  ASSERT_NE(console.find("done"), std::string::npos) << console;
  // ACK, then the listing's mode-change success reply 02 80 03 00 A0 00 10 16 0A.
  const std::vector<uint8_t> mode_ok = {0x06, 0x02, 0x80, 0x03, 0x00, 0xA0, 0x00, 0x10, 0x16, 0x0A};
  const std::regex step(R"((\d+)>(\d+) mode ([0-9a-f]*) status ([0-9a-f]*))");
  int steps = 0;
  for (const auto& line : lines_of(console)) {
    std::smatch m;
    if (!std::regex_search(line, m, step)) continue;
    ++steps;
    const uint32_t to = static_cast<uint32_t>(std::stoul(m[2]));
    EXPECT_EQ(from_hex(m[3]), mode_ok) << line;
    const std::vector<uint8_t> status = from_hex(m[4]);
    // ACK and the whole 0xB1 telegram: 1 + 4 + 1 + 152 + 1 + 2 bytes.
    ASSERT_EQ(status.size(), 161u) << line;
    EXPECT_EQ(std::vector<uint8_t>(status.begin(), status.begin() + 6),
              (std::vector<uint8_t>{0x06, 0x02, 0x80, 154, 0x00, 0xB1}))
        << line;
    const uint16_t crc = lms2xx_crc(status.data() + 1, 158);
    EXPECT_EQ(status[159], crc & 0xFF) << line;
    EXPECT_EQ(status[160], crc >> 8) << line;
    EXPECT_EQ(status[158], LMS2XX_STATUS_OK) << line;
    // The baud word (payload bytes 116-117) names the rate the reply came at.
    const size_t payload = 5;  // ACK, STX, address, two length bytes
    EXPECT_EQ(status[payload + 116] | (status[payload + 117] << 8), lms2xx_status_baud_code(to)) << line;
  }
  EXPECT_EQ(steps, 12) << console;  // every ordered pair of the four rates
}

}  // namespace
}  // namespace sear::test
