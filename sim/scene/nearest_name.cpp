#include "scene/nearest_name.hpp"

#include <algorithm>
#include <cctype>

namespace sear {
namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string nearest_name(const std::string& typed, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, typed.size() / 3) + 1;
  for (const auto& c : candidates) {
    // The distance is at least the difference in length: skip what cannot beat the best so far.
    const std::size_t length_gap = typed.size() > c.size() ? typed.size() - c.size() : c.size() - typed.size();
    if (length_gap >= best_distance) continue;
    const std::size_t d = edit_distance(typed, c);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

std::string did_you_mean(const std::string& typed, const std::vector<std::string>& candidates) {
  const std::string best = nearest_name(typed, candidates);
  return best.empty() ? std::string() : " (did you mean '" + best + "'?)";
}

std::string did_you_mean(const Diagnostics& diagnostics, const std::string& typed,
                         const std::vector<std::string>& candidates) {
  return diagnostics.full() ? std::string() : did_you_mean(typed, candidates);
}

std::string valid_names(const Diagnostics& diagnostics, const std::vector<std::string>& names, bool elements) {
  if (diagnostics.full() || names.empty()) return {};
  std::vector<std::string> seen;
  std::string out = "; valid: ";
  for (const auto& n : names) {
    if (std::find(seen.begin(), seen.end(), n) != seen.end()) continue;  // has() and number() both ask
    out += (seen.empty() ? "" : ", ") + (elements ? "<" + n + ">" : n);
    seen.push_back(n);
  }
  return out;
}

}  // namespace sear
