// One `sear test` case's finished run as suites of the suite's JUnit report, with paths made
// relative to the suite's folder so that shards run on different machines merge into the report a
// single run writes; and the lines a person reads for it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "expect/junit_report.hpp"

namespace sear {

struct FinishedCase {
  std::string scenario_path;  // as `sear run` was given it, relative to the suite's folder
  std::string scenario_file;  // the file read for it (a folder's project.xml), relative to the suite's folder
  std::string name;           // the scenario's name, for a run that left no report
  std::string project_file;   // absolute; empty when unknown
  std::uint64_t seed = 0;
  std::string junit;  // the report the run wrote (missing when it could not be done)
  std::string log;    // what it printed
  int exit_code = 0;
};

// The run's suites, read back from its report; a run that wrote none, or exited with a failure
// its report does not show (a crash after the verdicts), gives a suite with an error saying so
// and how the run ended. Absolute paths under `suite_dir` (canonical) become relative to it.
std::vector<JunitSuite> finished_case_suites(const FinishedCase& run, const std::filesystem::path& suite_dir);

// A file under the suite's folder that does not load (`errors`: the loader's diagnostics), as a
// suite of its own named by the file, with an error and no run: absolute paths under `suite_dir`
// become relative to it, as in a run's suite.
JunitSuite unloadable_file_suite(const std::string& file, const std::string& errors, std::uint64_t seed,
                                 const std::filesystem::path& suite_dir);

// Some expectation failed or the run could not be done.
bool suite_failed(const JunitSuite& suite);

// What a person reads when a case fails: every failed expectation with what was seen instead, or
// the run's error, each line indented.
std::string failure_lines(const JunitSuite& suite, const std::string& indent);

}  // namespace sear
