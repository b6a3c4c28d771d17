// Runs a shell command and keeps its standard output and exit code: for the tests that check what
// a tool (sear, can-utils, the vcan guest's programs) printed.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace sear::test {

struct CommandOutput {
  int exit_code = -1;  // -1 when it could not be started or was ended by a signal
  std::string out;
};

inline CommandOutput command_output(const std::string& command) {
  CommandOutput result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) result.out.append(buffer, n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

}  // namespace sear::test
