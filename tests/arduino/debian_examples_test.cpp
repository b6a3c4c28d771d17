// Debian's Arduino examples (arduino-core-avr's EEPROM sketches and Wire's i2c_scanner), unchanged: built for the host layer
// and run by `sear`, and built for the ATmega2560 with the genuine core and run on the AVR engine;
// what they print checked against what each example must do.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "firmware_run.hpp"

using namespace sear::test;

namespace {

// eeprom_read prints a line every 500 ms (three by 1.2 s); the others are done in 0.3 s (about 100
// bytes at 9600 baud).
// `eeprom`: an <eeprom> element, on the MCU's first line inside <mcu> (the project's line 9).
std::string project(const std::string& firmware_attribute, const std::string& engine = "native", double duration_s = 0.3,
                    const std::string& eeprom = "") {
  return rover_project("    <mcu name=\"main\" engine=\"" + engine + "\">\n" +
                           (eeprom.empty() ? "" : "      " + eeprom + "\n") + "      <firmware " + firmware_attribute +
                           "/>\n    </mcu>\n",
                       "", duration_s);
}

// The console's lines without their time stamps.
std::vector<std::string> console(const SearRun& run) {
  std::vector<std::string> out;
  for (const auto& line : lines_of(run.file("rover.main.console.log"))) out.push_back(line.substr(line.find(' ') + 1));
  return out;
}

// eeprom_read prints "address<TAB>value" every 500 ms from address 0: an erased chip reads 255.
TEST(DebianEepromRead, AnErasedChipReads255AtEveryAddress) {
  TempDir dir;
  const SearRun run = run_sear(dir, project(std::string("executable=\"") + EEPROM_READ + "\"", "native", 1.2));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::vector<std::string> want{"0\t255", "1\t255", "2\t255"};
  const auto got = console(run);
  ASSERT_GE(got.size(), want.size()) << run.file("rover.main.console.log");
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_EQ(got[i], want[i]);
}

// The first bytes eeprom_put leaves: 123.456f in IEEE 754 single precision, little-endian (as on
// the host and on the AVR), at address 0.
const std::string kPutFloat("\x79\xe9\xf6\x42", 4);

// eeprom_put writes 123.456f and {3.14159f, 65, "Working!"}; eeprom_get, run afterwards on the same
// MCU's kept EEPROM (<eeprom persist="true">: the file rover.main.eeprom beside the project, which
// outlives the run's output folder), reads them back as its comments say. Print gives floats 2
// decimals unless told 3.
TEST(DebianEepromPutGet, WhatOneRunPutsTheNextGetsWhenTheEepromPersists) {
  TempDir dir;
  const std::string keep = "<eeprom persist=\"true\"/>";
  const SearRun put = run_sear(dir, project(std::string("executable=\"") + EEPROM_PUT + "\"", "native", 0.3, keep));
  ASSERT_EQ(put.exit_code, 0) << put.err;
  EXPECT_EQ(console(put).at(0), "Written float data type!");
  const std::string cells = read_file(dir.path() / "rover.main.eeprom");
  ASSERT_EQ(cells.size(), 4096u);  // the ATmega2560's 4 KiB, erased past what was written
  EXPECT_EQ(cells.substr(0, 4), kPutFloat);
  EXPECT_EQ(static_cast<unsigned char>(cells[4095]), 0xFF);
  const SearRun get = run_sear(dir, project(std::string("executable=\"") + EEPROM_GET + "\"", "native", 0.3, keep));
  ASSERT_EQ(get.exit_code, 0) << get.err;
  const std::vector<std::string> want{"Read float from EEPROM: 123.456", "Read custom object from EEPROM: ", "3.14", "65",
                                      "Working!"};
  EXPECT_EQ(console(get), want) << get.file("rover.main.console.log");
}

// A bad <eeprom> is refused with the project file's line.
TEST(DebianEepromPutGet, ABadEepromElementNamesItsLine) {
  TempDir dir;
  const std::string firmware = std::string("executable=\"") + EEPROM_GET + "\"";
  SearRun run = run_sear(dir, project(firmware, "native", 0.3, "<eeprom persist=\"maybe\"/>"));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("project.xml:9: error:"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("persist"), std::string::npos) << run.err;
  run = run_sear(dir, project(firmware, "native", 0.3, "<eeprom file=\"no/such/folder/main.eeprom\"/>"));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("project.xml:9: error: <eeprom> file 'no/such/folder/main.eeprom' is in a folder that does "
                         "not exist"),
            std::string::npos)
      << run.err;
  run = run_sear(dir, project(firmware, "native", 0.3, "<eeprom persist=\"false\" file=\"main.eeprom\"/>"));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("project.xml:9: error: <eeprom> 'file' keeps the EEPROM"), std::string::npos) << run.err;
  run = run_sear(dir, project(firmware, "native", 0.3, "<eeprom persist=\"true\" size=\"4096\"/>"));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("project.xml:9: error:"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("file, persist"), std::string::npos) << run.err;  // the valid attributes
}

// Without persistence each run starts erased: the float's four 0xFF bytes are a NaN, and the
// structure's byte 255.
TEST(DebianEepromPutGet, WithoutPersistenceTheNextRunStartsErased) {
  TempDir dir;
  const SearRun get = run_sear(dir, project(std::string("executable=\"") + EEPROM_GET + "\""));
  ASSERT_EQ(get.exit_code, 0) << get.err;
  const auto got = console(get);
  ASSERT_GE(got.size(), 4u);
  EXPECT_EQ(got[0], "Read float from EEPROM: nan");
  EXPECT_EQ(got[2], "nan");
  EXPECT_EQ(got[3], "255");
}

// The same sketches built for the ATmega2560 with Debian's genuine core, on the AVR engine: the
// lines that do not depend on memory past the EEPROM's erased bytes match the host build's.
TEST(DebianExamplesOnTheChip, TheGenuineCoreBuildPrintsWhatTheHostBuildPrints) {
#ifndef EEPROM_READ_AVR
  GTEST_SKIP() << "this build has no AVR engine (engines/avr)";
#else
  TempDir dir;
  const SearRun chip = run_sear(dir, project(std::string("elf=\"") + EEPROM_READ_AVR + "\"", "avr", 1.2));
  ASSERT_EQ(chip.exit_code, 0) << chip.err;
  TempDir dir2;
  const SearRun host = run_sear(dir2, project(std::string("executable=\"") + EEPROM_READ + "\"", "native", 1.2));
  ASSERT_EQ(host.exit_code, 0) << host.err;
  EXPECT_EQ(console(chip), console(host));
  ASSERT_GE(console(chip).size(), 3u);

  TempDir dir3;
  const SearRun chip_get = run_sear(dir3, project(std::string("elf=\"") + EEPROM_GET_AVR + "\"", "avr"));
  ASSERT_EQ(chip_get.exit_code, 0) << chip_get.err;
  const auto got = console(chip_get);
  ASSERT_GE(got.size(), 4u);
  EXPECT_EQ(got[0], "Read float from EEPROM: nan");
  EXPECT_EQ(got[3], "255");
#endif
}

// The chip keeps its EEPROM in the same attribute's file: what the genuine core's eeprom_put wrote
// on the AVR engine is in the file, eeprom_get on the chip reads it back in the next run, and so
// does the host build, whose float and struct have the same bytes.
TEST(DebianExamplesOnTheChip, TheKeptEepromPersistsOnTheAvrEngineAndAcrossEngines) {
#ifndef EEPROM_PUT_AVR
  GTEST_SKIP() << "this build has no AVR engine (engines/avr)";
#else
  TempDir dir;
  const std::string keep = "<eeprom file=\"chip.eeprom\"/>";
  const SearRun put = run_sear(dir, project(std::string("elf=\"") + EEPROM_PUT_AVR + "\"", "avr", 0.3, keep));
  ASSERT_EQ(put.exit_code, 0) << put.err;
  EXPECT_EQ(console(put).at(0), "Written float data type!");
  const std::string cells = read_file(dir.path() / "chip.eeprom");
  ASSERT_EQ(cells.size(), 4096u);
  EXPECT_EQ(cells.substr(0, 4), kPutFloat);
  const std::vector<std::string> want{"Read float from EEPROM: 123.456", "Read custom object from EEPROM: ", "3.14", "65",
                                      "Working!"};
  const SearRun chip_get = run_sear(dir, project(std::string("elf=\"") + EEPROM_GET_AVR + "\"", "avr", 0.3, keep));
  ASSERT_EQ(chip_get.exit_code, 0) << chip_get.err;
  EXPECT_EQ(console(chip_get), want);
  const SearRun host_get = run_sear(dir, project(std::string("executable=\"") + EEPROM_GET + "\"", "native", 0.3, keep));
  ASSERT_EQ(host_get.exit_code, 0) << host_get.err;
  EXPECT_EQ(console(host_get), want);
#endif
}

// Wire's i2c_scanner addresses 1..126 in turn and names those that acknowledge: on a bus with the
// project's MPU-6050 (0x68, AD0 low) and HMC5883L (0x1E, fixed: datasheet) exactly those two, in
// address order, on the host layer and with the genuine Wire library on the chip alike. An empty
// bus is "No I2C devices found". The scan and its lines at 9600 baud are done by 0.12 s.
std::string i2c_project(const std::string& firmware_attribute, const std::string& engine, bool devices) {
  return rover_project("    <mcu name=\"main\" engine=\"" + engine + "\">\n      <firmware " + firmware_attribute + "/>\n" +
                           (devices ? "      <mpu6050 name=\"imu\" pos=\"0 0 0.05\"/>\n"
                                      "      <hmc5883l name=\"compass\" pos=\"0 0 0.1\"/>\n"
                                    : "") +
                           "    </mcu>\n",
                       "", 0.3);
}

void expect_scan(const SearRun& run, bool devices) {
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::vector<std::string> want =
      devices ? std::vector<std::string>{"", "I2C Scanner", "Scanning...", "I2C device found at address 0x1E  !",
                                         "I2C device found at address 0x68  !", "done", ""}
              : std::vector<std::string>{"", "I2C Scanner", "Scanning...", "No I2C devices found", ""};
  EXPECT_EQ(console(run), want) << run.file("rover.main.console.log");
}

TEST(DebianWireExamples, TheI2cScannerFindsTheDevicesTheProjectWires) {
  for (const bool devices : {true, false}) {
    TempDir dir;
    expect_scan(run_sear(dir, i2c_project(std::string("executable=\"") + I2C_SCANNER + "\"", "native", devices)), devices);
  }
}

TEST(DebianWireExamples, TheI2cScannerOnTheChipFindsTheSame) {
#ifndef I2C_SCANNER_AVR
  GTEST_SKIP() << "this build has no AVR engine (engines/avr)";
#else
  for (const bool devices : {true, false}) {
    TempDir dir;
    expect_scan(run_sear(dir, i2c_project(std::string("elf=\"") + I2C_SCANNER_AVR + "\"", "avr", devices)), devices);
  }
#endif
}

}  // namespace
