// Editing a project's text in a test: the line of a snippet, for expected file:line messages, and
// one snippet replaced by another, for variants of a valid project.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace sear::test {

// 1-based line of the first occurrence of `needle` in `text`, 0 when absent.
inline int line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  if (at == std::string::npos) return 0;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

// `text` with its one occurrence of `from` replaced by `to`; a test typo fails loudly.
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "'" << from << "' is not in the text";
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << "'" << from << "' is in the text twice";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

}  // namespace sear::test
