// Text for people on standard output: the console echo and the end-of-run summary. Standard
// output may be a pipe that closes early (`sear run | head -2`), so a failed write ends all later
// printing there, never the run or its files.
#pragma once

#include <string_view>

namespace sear {

void print_to_stdout(std::string_view text);

}  // namespace sear
