// "Did you mean ...?" for misspelt element and attribute names in project files.
#pragma once

#include <string>
#include <vector>

namespace sear {

// The candidate closest to `typed` by edit distance, or "" when none is plausibly a misspelling.
// Hand-written: no Debian library offers a plain edit distance for C++.
std::string nearest_name(const std::string& typed, const std::vector<std::string>& candidates);

// " (did you mean 'x'?)" or "" when there is nothing close.
std::string did_you_mean(const std::string& typed, const std::vector<std::string>& candidates);

}  // namespace sear
