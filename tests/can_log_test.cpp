// The candump log: lines as can-utils 2020.11 writes them, read back by its own log2long.
#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "exporters/candump_log.hpp"
#include "command_output.hpp"
#include "temp_dir.hpp"

namespace sear {
namespace {

CanTransfer transfer(std::int64_t end_ns, std::uint32_t id, bool extended, bool remote, std::vector<std::uint8_t> data,
                     std::uint8_t remote_dlc = 0, bool acked = true) {
  CanTransfer t;
  t.end_ns = end_ns;
  t.start_ns = end_ns - 100'000;
  t.frame.id = id;
  t.frame.extended = extended;
  t.frame.remote = remote;
  t.frame.dlc = remote ? remote_dlc : static_cast<std::uint8_t>(data.size());
  for (std::size_t i = 0; i < data.size(); ++i) t.frame.data[i] = data[i];
  t.acked = acked;
  return t;
}

TEST(CandumpLog, LinesAsCandumpWritesThem) {
  EXPECT_EQ(CandumpLog::line("can0", transfer(1'000'250'999, 0x123, false, false, {0xDE, 0xAD, 0xBE, 0xEF})),
            "(0000000001.000250) can0 123#DEADBEEF\n");
  EXPECT_EQ(CandumpLog::line("vcan0", transfer(0, 0x1ABCDEF, true, false, {})),
            "(0000000000.000000) vcan0 01ABCDEF#\n");
  EXPECT_EQ(CandumpLog::line("can1", transfer(86'400'000'000'000, 0x7, false, true, {}, 0)),
            "(0000086400.000000) can1 007#R\n");
  EXPECT_EQ(CandumpLog::line("can1", transfer(999, 0x1FFFFFFF, true, true, {}, 8)),
            "(0000000000.000000) can1 1FFFFFFF#R8\n");
  EXPECT_THROW(CandumpLog("/dev/null", "a name with blanks", 1000), std::invalid_argument);
  EXPECT_THROW(CandumpLog("/dev/null", "sixteen_chars_xx", 1000), std::invalid_argument);
}

std::string log2long(const std::string& path) {
  return test::command_output("/usr/bin/log2long < '" + path + "' 2>&1").out;
}

TEST(CandumpLog, Log2longReadsTheFile) {
  test::TempDir dir;
  const std::string path = (dir.path() / "bus.candump.log").string();
  {
    CandumpLog log(path, "sear0", 1 << 20);
    log.write(transfer(1'500'000, 0x123, false, false, {0x01, 0x02, 0xA0}));
    log.write(transfer(1'600'000, 0x555, false, false, {0x99}, 0, false));  // not acked: left out
    log.write(transfer(2'000'001'000, 0x12345678, true, false, {0, 0xFF, 0x10, 0x20, 0x30, 0x40, 0x50, 0x60}));
    log.write(transfer(3'000'000'000, 0x7FF, false, true, {}, 5));
    log.write(transfer(3'100'000'000, 0x000, false, false, {}));
    log.flush();
    // Flushed: on disk before the log is closed, as for a run killed mid-way.
    const std::string out = log2long(path);
    std::istringstream lines(out);
    std::vector<std::string> got;
    for (std::string line; std::getline(lines, line);) {
      std::istringstream l(line);
      std::string stamp, iface, id, dlc, rest;
      l >> stamp >> iface >> id >> dlc;
      std::getline(l, rest);
      // log2long pads the data and appends the ASCII column: keep the hex bytes (or the remote mark).
      std::istringstream r(rest);
      std::string word, bytes;
      while (r >> word && word.size() == 2 && word.find('\'') == std::string::npos) bytes += word;
      if (rest.find("remote request") != std::string::npos) bytes = "remote";
      got.push_back(stamp + " " + iface + " " + id + " " + dlc + " " + bytes);
    }
    EXPECT_EQ(got,
              (std::vector<std::string>{
                  "(0000000000.001500) sear0 123 [3] 0102A0", "(0000000002.000001) sear0 12345678 [8] 00FF102030405060",
                  "(0000000003.000000) sear0 7FF [5] remote", "(0000000003.100000) sear0 000 [0] "}))
        << out;
  }
}

TEST(CandumpLog, StaysWithinItsLimit) {
  test::TempDir dir;
  const std::string path = (dir.path() / "bus.candump.log").string();
  const std::uint64_t limit = 400;
  {
    CandumpLog log(path, "can0", limit);
    for (int i = 0; i < 100; ++i) log.write(transfer(i * 1'000'000, 0x100, false, false, {1, 2}));
    log.flush();
    EXPECT_TRUE(log.file().truncated());
  }
  std::FILE* f = std::fopen(path.c_str(), "rb");
  ASSERT_NE(f, nullptr);
  std::fseek(f, 0, SEEK_END);
  EXPECT_LE(std::ftell(f), static_cast<long>(limit));
  std::fclose(f);
  // Every whole line before the note still reads; the note is a comment line, which canplayer
  // skips and log2long stops at.
  const std::string out = log2long(path);
  EXPECT_NE(out.find("(0000000000.001000)  can0       100   [2]  01 02"), std::string::npos) << out;
}

}  // namespace
}  // namespace sear
