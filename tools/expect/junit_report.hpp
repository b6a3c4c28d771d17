// Scenario runs as a JUnit XML report, the format CI systems (Jenkins, GitLab, ...) display: one
// <testsuite> per run of a scenario with a seed, one <testcase> per expectation. Written and read
// with tinyxml2, so that reports of shards merge into the very report a single run would write.
//
// Fields, as in the Jenkins xunit plugin's junit-10.xsd (no schema is packaged in Debian):
//   <testsuites name="sear" tests failures errors time>
//     <testsuite name="SCENARIO (seed N)" tests failures errors skipped="0" time>
//       <properties> <property name="scenario|project|seed" value/> </properties>
//       <testcase classname="SCENARIO" name="EXPECTATION" time>
//         [<failure message="what was seen" type="expectation">the verdict line and where</failure>]
//         [<error message type="run">: the run itself failed (its one test case, named "run")]
//       </testcase>
//       <system-out>the console log(s)</system-out>
//     </testsuite>
//   </testsuites>
// Times are simulated seconds with millisecond resolution: a test case's is when its verdict fell,
// a suite's the run's length, so that the same run always writes the same report. No timestamp or
// hostname, for the same reason.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "expect/expectation_checker.hpp"

namespace sear {

struct JunitCase {
  std::string name;
  std::int64_t time_ns = 0;
  bool failed = false;
  std::string message;  // failures: what was seen instead
  std::string detail;   // failures: the full verdict and where the expectation is written
};

struct JunitSuite {
  std::string scenario;       // its name: the test cases' classname
  std::string scenario_file;  // where it is written
  std::string project_file;
  std::uint64_t seed = 0;
  std::int64_t time_ns = 0;   // the run's simulated length
  std::vector<JunitCase> cases;
  std::string error;          // non-empty: the run could not be done (firmware build, load, crash of sear)
  std::string system_out;     // the console logs, as the caller gathered them

  std::string name() const;  // "SCENARIO (seed N)"
};

// One run's suite from its checker (after finish()).
JunitSuite junit_suite(const Scenario& scenario, std::uint64_t seed, const ExpectationChecker& checker,
                       std::int64_t end_ns, std::string system_out);

// Writes `suites` to `path`, ordered by scenario, seed and file so that the order they ran in does
// not matter. Throws std::runtime_error naming the file when it cannot be written.
void write_junit(const std::string& path, std::vector<JunitSuite> suites);

// The suites of a report write_junit() wrote. Throws std::runtime_error naming the file and line
// when it cannot be read or is not such a report.
std::vector<JunitSuite> read_junit(const std::string& path);

// Joins the suites of several reports (shards of one suite) into one, identical to the report a
// single run of all of them writes.
void merge_junit(const std::vector<std::string>& inputs, const std::string& output);

}  // namespace sear
