#include "exporters/stdout_text.hpp"

#include <cstdio>

namespace sear {
namespace {

bool g_stdout_open = true;  // one standard output per process, closed for good once a write fails

}  // namespace

void print_to_stdout(std::string_view text) {
  if (!g_stdout_open) return;
  if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() || std::fflush(stdout) != 0) g_stdout_open = false;
}

}  // namespace sear
