// tools/sear/sketch_build: a sketch folder as the IDE sees one (more .ino tabs, .cpp/.h files, a
// libraries/ folder beside it) becomes a firmware that runs; what the layer refuses is told by file
// and line.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "firmware_run.hpp"
#include "sear/sketch_build.hpp"

using namespace sear::test;
namespace fs = std::filesystem;

namespace {

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

sear::SketchToolchain toolchain(const TempDir& dir) {
  setenv("SEAR_CACHE_DIR", (dir.path() / "cache").c_str(), 1);
  return sear::default_sketch_toolchain();
}

// Two tabs (twice() in the second, used before it is defined), a .cpp and a .c with headers, and a
// library in libraries/ beside the sketch, as the IDE resolves them.
TEST(SketchBuild, AFolderWithTabsFilesAndItsOwnLibraryBuildsAndRuns) {
  TempDir dir;
  const fs::path sketch = dir.path() / "Counter";
  write(sketch / "Counter.ino",
        "#include <Tally.h>\n#include \"offset.h\"\n#include \"same.h\"\nTally tally;\n"
        "void setup() { Serial.begin(115200); }\n"
        "void loop() { tally.add(same(twice(3)) + offset()); Serial.print(\"tally \"); Serial.println(tally.total()); delay(100); }\n");
  // A C file, compiled as C (a C++ compiler would reject the implicit conversion from void *).
  write(sketch / "same.h", "#pragma once\n#ifdef __cplusplus\nextern \"C\"\n#endif\nint same(int x);\n");
  write(sketch / "same.c", "#include <stdlib.h>\n#include \"same.h\"\nint same(int x) { int *p = malloc(sizeof *p); *p = x; x = *p; free(p); return x; }\n");
  write(sketch / "second.ino", "int twice(int x) { return 2 * x; }\n");
  write(sketch / "offset.h", "#pragma once\nint offset();\n");
  write(sketch / "offset.cpp", "#include \"offset.h\"\nint offset() { return 1; }\n");
  write(sketch / "libraries" / "Tally" / "src" / "Tally.h",
        "#pragma once\nclass Tally { public: void add(int v); long total() const { return total_; } private: long total_ = 0; };\n");
  write(sketch / "libraries" / "Tally" / "src" / "Tally.cpp", "#include \"Tally.h\"\nvoid Tally::add(int v) { total_ += v; }\n");
  // arduino-builder 1.3 wants every field of a 1.5-layout library's properties.
  write(sketch / "libraries" / "Tally" / "library.properties",
        "name=Tally\nversion=1.0.0\nauthor=SEAR\nmaintainer=SEAR\nsentence=Counts.\nparagraph=\ncategory=Other\n"
        "url=\narchitectures=*\n");
  const std::string exe = sear::build_sketch("counter", (sketch / "").string(), {}, toolchain(dir));
  const SearRun run = run_sear(dir, rover_project("    <mcu name=\"main\">\n      <firmware executable=\"" + exe +
                                                      "\"/>\n    </mcu>\n",
                                                  "", 0.25));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // Each pass adds 2 * 3 + 1 = 7; passes at 0, 0.1 and 0.2 s.
  const auto lines = lines_of(run.file("rover.main.console.log"));
  ASSERT_EQ(lines.size(), 3u) << run.file("rover.main.console.log");
  EXPECT_NE(lines[0].find(" tally 7"), std::string::npos);
  EXPECT_NE(lines[2].find(" tally 21"), std::string::npos);
}

TEST(SketchBuild, AFolderWithoutItsOwnInoIsNotASketch) {
  TempDir dir;
  write(dir.path() / "Robot" / "other.ino", "void setup() {}\nvoid loop() {}\n");
  try {
    sear::build_sketch("robot", (dir.path() / "Robot").string(), {}, toolchain(dir));
    FAIL() << "built";
  } catch (const sear::FirmwareBuildError& e) {
    EXPECT_NE(std::string(e.what()).find("Robot.ino is missing"), std::string::npos) << e.what();
  }
}

// Register-level code stops the build with the register's name at the sketch's own file and line
// (the IDE's #line directives keep them).
TEST(SketchBuild, RegisterLevelCodeIsRefusedByNameFileAndLine) {
  TempDir dir;
  const fs::path sketch = dir.path() / "Blinky";
  write(sketch / "Blinky.ino", "void setup() {\n  DDRB |= _BV(7);\n}\nvoid loop() {\n  PORTB ^= _BV(7);\n}\n");
  try {
    sear::build_sketch("blinky", sketch.string(), {}, toolchain(dir));
    FAIL() << "built";
  } catch (const sear::FirmwareBuildError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("Blinky.ino:2:"), std::string::npos) << what;
    EXPECT_NE(what.find("sear_register_DDRB_is_not_modelled_on_the_host_build_use_the_HAL_or_the_AVR_engine"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("Blinky.ino:5:"), std::string::npos) << what;
  }
}

}  // namespace
