// A native run also compiles the firmware for the ATmega2560 (issue 22, tools/sear/chip_check.cpp):
// what only the chip's 16-bit int makes wrong is shown on stderr, once a run, from a cache that
// compiles again only when a source changes; a firmware the chip cannot compile still runs here.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "firmware_run.hpp"
#include "scoped_env.hpp"

namespace sear::test {
namespace {

namespace fs = std::filesystem;

constexpr const char* kChip = "on the ATmega2560 (16-bit int): ";

// 1000 * 100 = 100000: it fits a 32-bit int (no warning from the host's gcc), not a 16-bit one
// (INT_MAX 32767), where avr-gcc warns -Woverflow. Line 6 holds it.
const std::string kOverflowing =
    "#include <hal/hal.h>\n"
    "\n"
    "int main(void) {\n"
    "  hal_init();\n"
    "  uart_begin(0, 115200);\n"
    "  long n = 1000 * 100;\n"
    "  for (;;) {\n"
    "    uart_print(0, n > 50000 ? \"big\\n\" : \"small\\n\");\n"
    "    delay_ms(100);\n"
    "  }\n"
    "}\n";

// The same firmware done right for both: the product is computed in long on either.
const std::string kPortable =
    "#include <hal/hal.h>\n"
    "\n"
    "int main(void) {\n"
    "  hal_init();\n"
    "  uart_begin(0, 115200);\n"
    "  long n = 1000L * 100;\n"
    "  for (;;) {\n"
    "    uart_print(0, n > 50000 ? \"big\\n\" : \"small\\n\");\n"
    "    delay_ms(100);\n"
    "  }\n"
    "}\n";

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}


// A folder whose firmware cache is its own, and whose avr-gcc and avr-g++ ($AVR_CC, $AVR_CXX) are
// the real ones behind scripts that note each compile ("-c") in compiles.log: the evidence of a
// compile, free of timing.
class ChipRun : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::string(AVR_GCC).empty()) GTEST_SKIP() << "avr-gcc is not installed (gcc-avr, avr-libc)";
    cache_.emplace("SEAR_CACHE_DIR", (dir_.path() / "cache").string());
    c_compiler_.emplace("AVR_CC", noting("avr-gcc"));
    cxx_compiler_.emplace("AVR_CXX", noting("avr-g++"));  // a sketch's C++
  }
  // A script in the folder that notes each compile and runs `program` from avr-gcc's folder.
  std::string noting(const std::string& program) const {
    const std::string log = (dir_.path() / "compiles.log").string();
    const std::string real = (fs::path(AVR_GCC).parent_path() / program).string();
    const std::string script = dir_.write(
        program, "#!/bin/sh\nfor a in \"$@\"; do [ \"$a\" = -c ] && echo \"$*\" >>'" + log + "'; done\nexec '" +
                     real + "' \"$@\"\n");
    fs::permissions(script, fs::perms::owner_all);
    return script;
  }
  std::size_t compiles() const { return lines_of(read_file(dir_.path() / "compiles.log")).size(); }
  SearRun run(const std::string& firmware) {
    dir_.write("main.c", firmware);
    return run_sear(dir_, rover_project("    <mcu name=\"main\">\n      <firmware sources=\"main.c\"/>\n    </mcu>\n",
                                        "", 0.25));
  }
  std::string source() const { return (dir_.path() / "main.c").string(); }

  TempDir dir_;
  std::optional<ScopedEnv> cache_, c_compiler_, cxx_compiler_;
};

TEST_F(ChipRun, AnIntThatOverflowsOnlyOnTheChipIsShownOnceWithItsFileAndLine) {
  const auto first = run(kOverflowing);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_EQ(count(first.err, std::string(kChip) + source() + ":6:"), 1u) << first.err;
  EXPECT_EQ(count(first.err, "[-Woverflow]"), 1u) << first.err;
  EXPECT_EQ(count(first.err, "warning"), 1u) << first.err;  // the host's gcc had nothing to say
  EXPECT_EQ(compiles(), 1u);                                 // main.c, once; the AVR HAL is not needed
  // The natively run firmware computed 100000, as a 32-bit int does.
  EXPECT_NE(first.file("rover.main.console.log").find("big"), std::string::npos);
  // The run's files are the same with or without avr-gcc: the warning is on stderr only.
  for (const auto& entry : fs::directory_iterator(first.dir))
    EXPECT_EQ(read_file(entry.path()).find("ATmega2560"), std::string::npos) << entry.path();
}

TEST_F(ChipRun, ASecondRunShowsTheWarningAgainFromTheCacheWithoutCompiling) {
  const auto first = run(kOverflowing);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  ASSERT_EQ(compiles(), 1u);
  const auto second = run(kOverflowing);
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(compiles(), 1u) << "the unchanged firmware was compiled again";
  EXPECT_EQ(count(second.err, std::string(kChip) + source() + ":6:"), 1u) << second.err;
  // A changed source is compiled again, and the fixed line warns no more.
  const auto fixed = run(kPortable);
  ASSERT_EQ(fixed.exit_code, 0) << fixed.err;
  EXPECT_EQ(compiles(), 2u);
  EXPECT_EQ(fixed.err.find(kChip), std::string::npos) << fixed.err;
}

TEST_F(ChipRun, AFirmwareRightForBothShowsNoChipWarning) {
  const auto clean = run(kPortable);
  ASSERT_EQ(clean.exit_code, 0) << clean.err;
  EXPECT_EQ(compiles(), 1u);  // it was looked at
  EXPECT_EQ(clean.err.find(kChip), std::string::npos) << clean.err;
  EXPECT_EQ(clean.err.find("warning"), std::string::npos) << clean.err;
}

TEST_F(ChipRun, AWarningTheHostGivesTooIsShownOnlyAsTheHosts) {
  // An unused variable: both compilers warn (-Wall) at line 4; only the host's line is shown.
  const auto run_result = run("#include <hal/hal.h>\n\nint main(void) {\n  int unused;\n  hal_init();\n"
                              "  for (;;) delay_ms(100);\n}\n");
  ASSERT_EQ(run_result.exit_code, 0) << run_result.err;
  EXPECT_EQ(compiles(), 1u);
  EXPECT_EQ(count(run_result.err, source() + ":4:"), 1u) << run_result.err;
  EXPECT_EQ(run_result.err.find(kChip), std::string::npos) << run_result.err;
}

TEST_F(ChipRun, AFirmwareTheChipCannotCompileRunsHereWithOneLineSayingWhy) {
  // <pthread.h> is the host's; avr-libc has none. Line 2 includes it.
  const auto run_result =
      run("#include <hal/hal.h>\n#include <pthread.h>\n\nint main(void) {\n  hal_init();\n"
          "  uart_begin(0, 115200);\n  uart_print(0, \"ran\\n\");\n  for (;;) delay_ms(100);\n}\n");
  ASSERT_EQ(run_result.exit_code, 0) << run_result.err;
  EXPECT_EQ(count(run_result.err, "does not compile for the ATmega2560"), 1u) << run_result.err;
  EXPECT_EQ(count(run_result.err, source() + ":2:"), 1u) << run_result.err;
  EXPECT_NE(run_result.err.find("pthread.h"), std::string::npos) << run_result.err;
  EXPECT_NE(run_result.file("rover.main.console.log").find("ran"), std::string::npos);
}

// A sketch is compiled for the chip as the IDE does, against Debian's genuine core: the same
// overflow, at its line of the .ino (arduino-builder's #line directives), then from the cache.
TEST_F(ChipRun, ASketchIsLookedAtAsTheIdeWouldBuildIt) {
  if (!SKETCHES) GTEST_SKIP() << "this sear was built without the Arduino layer (arduino-core-avr, arduino-builder)";
  const std::string ino = dir_.write("Over/Over.ino",
                                     "void setup() { Serial.begin(115200); }\n"
                                     "\n"
                                     "void loop() {\n"
                                     "  long n = 1000 * 100;\n"
                                     "  Serial.println(n > 50000 ? \"big\" : \"small\");\n"
                                     "  delay(100);\n"
                                     "}\n");
  const std::string project = rover_project("    <mcu name=\"main\">\n      <firmware sketch=\"Over\"/>\n    </mcu>\n",
                                            "", 0.25);
  const auto first = run_sear(dir_, project);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_EQ(count(first.err, std::string(kChip) + ino + ":4:"), 1u) << first.err;
  EXPECT_EQ(count(first.err, "[-Woverflow]"), 1u) << first.err;
  EXPECT_EQ(compiles(), 1u);  // the preprocessed Over.ino.cpp; the core is not compiled
  const auto second = run_sear(dir_, project);
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(compiles(), 1u) << "the unchanged sketch was compiled again";
  EXPECT_EQ(count(second.err, std::string(kChip) + ino + ":4:"), 1u) << second.err;
}

TEST(ChipRunWithoutAvrGcc, SaysSoOnceAndRuns) {
  TempDir dir;
  const ScopedEnv cache("SEAR_CACHE_DIR", (dir.path() / "cache").string());
  const ScopedEnv compiler("AVR_CC", (dir.path() / "no-avr-gcc").string());
  dir.write("main.c", kOverflowing);
  const auto run = run_sear(
      dir, rover_project("    <mcu name=\"main\">\n      <firmware sources=\"main.c\"/>\n    </mcu>\n", "", 0.25));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(count(run.err, "no-avr-gcc not found"), 1u) << run.err;
  EXPECT_EQ(run.err.find(kChip), std::string::npos) << run.err;
}

}  // namespace
}  // namespace sear::test
