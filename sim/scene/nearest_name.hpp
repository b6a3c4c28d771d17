// "Did you mean ...?" for misspelt element and attribute names in project files.
#pragma once

#include <string>
#include <vector>

#include "scene/diagnostics.hpp"

namespace sear {

// The candidate closest to `typed` by edit distance, or "" when none is plausibly a misspelling.
// Hand-written: no Debian library offers a plain edit distance for C++. Linear in the number of
// candidates; a candidate whose length alone rules it out costs nothing.
std::string nearest_name(const std::string& typed, const std::vector<std::string>& candidates);

// " (did you mean 'x'?)" or "" when there is nothing close.
std::string did_you_mean(const std::string& typed, const std::vector<std::string>& candidates);

// The same, but "" once `diagnostics` keeps no more errors: a file with many misspellings
// against many names would otherwise cost errors x names edit distances for text never shown.
std::string did_you_mean(const Diagnostics& diagnostics, const std::string& typed,
                         const std::vector<std::string>& candidates);

// "; valid: a, b, c" (elements: "<a>, <b>"), each name once in the order given, so that a
// misspelling too far from any name for a suggestion still shows what could be written there;
// "" when there are none, or once `diagnostics` keeps no more errors.
std::string valid_names(const Diagnostics& diagnostics, const std::vector<std::string>& names, bool elements = false);

}  // namespace sear
