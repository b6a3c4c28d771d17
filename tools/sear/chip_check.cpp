// See chip_check.hpp.
#include "sear/chip_check.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdlib>
#include <regex>
#include <set>
#include <sstream>

#include "runtime/process_keeper.hpp"

namespace sear {
namespace {

// gcc's "file:line:col: warning: text [-Wflag]" (the column and the option are optional).
const std::regex& warning_line() {
  static const std::regex kWarning(R"(^(.+?):(\d+):(?:(\d+):)? warning: (.*?)(?: \[(-W[^\]]+)\])?$)");
  return kWarning;
}

// Where a warning is and which option gave it: what the two compilers agree on when they warn about
// the same thing in words of their own versions.
std::string warning_place(const std::smatch& m) { return m[1].str() + ":" + m[2].str() + ":" + m[5].str(); }

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The compiler's own key of one firmware: what goes into its build, apart from which MCU runs it.
std::string build_key(const ChipFirmware& firmware) {
  std::string key;
  const auto add = [&key](const std::vector<std::string>& list) {
    for (const auto& item : list) key += item + '\n';
    key += '\0';
  };
  add(firmware.sources);
  add(firmware.toolchain.compile_flags);
  add(firmware.toolchain.defines);
  add(firmware.toolchain.include_dirs);
  add(firmware.toolchain.extra_flags);
  add({firmware.toolchain.c_std, firmware.toolchain.cxx_std});
  return key;
}

// The line of a failed build's messages a reader needs first: the compiler's first error, or the
// linker's complaint, should one ever come (collect2's "ld returned 1" only says that there was one).
std::string first_error(const std::string& what) {
  const std::vector<std::string> lines = lines_of(what);
  for (const auto& line : lines) {
    if (line.rfind("collect2", 0) == 0) continue;
    if (line.find("error:") != std::string::npos || line.find("undefined reference") != std::string::npos ||
        line.find("overflowed by") != std::string::npos)
      return line;
  }
  for (std::size_t i = 1; i < lines.size(); ++i)  // the first line names the firmware
    if (!lines[i].empty()) return lines[i];
  return lines.empty() ? what : lines.front();
}

}  // namespace

bool program_found(const std::string& program) {
  if (program.find('/') != std::string::npos) return access(program.c_str(), X_OK) == 0;
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (access(((dir.empty() ? "." : dir) + "/" + program).c_str(), X_OK) == 0) return true;
  return false;
}

std::future<std::vector<ChipOutcome>> start_chip_builds(std::vector<ChipFirmware> firmware) {
  keeper_start();  // before a second thread could start it too
  return std::async(std::launch::async, [firmware = std::move(firmware)] {
    std::vector<ChipOutcome> outcomes;
    std::set<std::string> built;
    for (const auto& one : firmware) {
      if (!built.insert(build_key(one)).second) continue;
      ChipOutcome outcome{one.id, "", ""};
      try {
        outcome.compiler_output = cached_compiler_output(build_firmware(one.name, one.sources, one.toolchain));
      } catch (const FirmwareBuildInterrupted&) {
        throw;
      } catch (const std::exception& e) {
        outcome.error = e.what();
      }
      outcomes.push_back(std::move(outcome));
    }
    return outcomes;
  });
}

std::string chip_report(const ChipOutcome& outcome, const std::string& host_output) {
  if (!outcome.error.empty())
    return fmt::format("sear: {}: the firmware does not compile for the ATmega2560 (the native run goes on): {}\n",
                       outcome.id, first_error(outcome.error));
  std::set<std::string> host_places;
  std::smatch m;
  for (const auto& line : lines_of(host_output))
    if (std::regex_match(line, m, warning_line())) host_places.insert(warning_place(m));
  std::string report;
  std::set<std::string> shown;  // a header's warning comes once for each source including it
  for (const auto& line : lines_of(outcome.compiler_output)) {
    if (!std::regex_match(line, m, warning_line()) || host_places.count(warning_place(m))) continue;
    if (shown.insert(line).second) report += "on the ATmega2560 (16-bit int): " + line + "\n";
  }
  return report;
}

}  // namespace sear
