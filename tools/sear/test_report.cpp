#include "sear/test_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace sear {
namespace fs = std::filesystem;
namespace {

// The end of a run's output is where its error is; a firmware's endless warnings are not needed.
constexpr std::size_t kLogTailLines = 20;

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

struct Relative {
  fs::path dir;
  std::string prefix;  // "DIR/"

  std::string path(const std::string& p) const {
    if (p.empty() || !fs::path(p).is_absolute()) return p;
    return fs::path(p).lexically_normal().lexically_relative(dir).generic_string();
  }
  std::string text(const std::string& t) const { return replace_all(t, prefix, ""); }
};

std::string log_tail(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream all;
  all << in.rdbuf();
  std::string text = all.str();
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  std::size_t start = text.size();
  for (std::size_t lines = 0; start > 0 && lines < kLogTailLines; ++lines) {
    const std::size_t nl = text.rfind('\n', start - 1);
    start = nl == std::string::npos ? 0 : nl;
  }
  return text.substr(start == 0 ? 0 : start + 1);
}

std::string how_it_ended(int code) {
  if (code == 127) return "sear run could not be started";
  if (code > 128) return fmt::format("sear run ended by signal {}", code - 128);
  return fmt::format("sear run exited with code {}", code);
}

}  // namespace

bool suite_failed(const JunitSuite& suite) {
  return !suite.error.empty() ||
         std::any_of(suite.cases.begin(), suite.cases.end(), [](const JunitCase& c) { return c.failed; });
}

std::vector<JunitSuite> finished_case_suites(const FinishedCase& run, const fs::path& suite_dir) {
  const Relative relative{suite_dir, suite_dir.string() + "/"};
  std::vector<JunitSuite> suites;
  std::string unreadable;
  if (fs::exists(run.junit)) {
    try {
      suites = read_junit(run.junit);
    } catch (const std::runtime_error& e) {
      unreadable = e.what();
    }
  }
  const bool shown = std::any_of(suites.begin(), suites.end(), suite_failed);
  if (suites.empty() || (run.exit_code != 0 && !shown)) {
    std::string error = how_it_ended(run.exit_code);
    if (!unreadable.empty()) error += "; its report: " + unreadable;
    const std::string tail = log_tail(run.log);
    if (!tail.empty()) error += ":\n" + tail;
    if (suites.empty()) {
      JunitSuite s;
      s.scenario = run.name;
      s.scenario_file = run.scenario_file;
      s.project_file = run.project_file;
      s.seed = run.seed;
      suites.push_back(std::move(s));
    }
    suites.front().error = error;
  }
  for (JunitSuite& s : suites) {
    s.scenario_file = relative.path(s.scenario_file);
    s.project_file = relative.path(s.project_file);
    s.error = relative.text(s.error);
    s.system_out = relative.text(s.system_out);
    for (JunitCase& c : s.cases) {
      c.message = relative.text(c.message);
      c.detail = relative.text(c.detail);
    }
  }
  return suites;
}

JunitSuite unloadable_file_suite(const std::string& file, const std::string& errors, std::uint64_t seed,
                                 const fs::path& suite_dir) {
  const Relative relative{suite_dir, suite_dir.string() + "/"};
  JunitSuite s;
  s.scenario = file;
  s.scenario_file = file;
  s.seed = seed;
  std::string text = relative.text(errors);
  while (!text.empty() && text.back() == '\n') text.pop_back();
  s.error = "the file does not load:\n" + text;
  return s;
}

std::string failure_lines(const JunitSuite& suite, const std::string& indent) {
  std::string out;
  const auto add = [&](const std::string& text) {
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) out += indent + line + "\n";
  };
  if (!suite.error.empty()) add(suite.error);
  for (const JunitCase& c : suite.cases)
    if (c.failed) add(c.detail.empty() ? fmt::format("{}: {}", c.name, c.message) : c.detail);
  return out;
}

}  // namespace sear
