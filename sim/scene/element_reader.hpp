// Reads one XML element of a project file with validation: every attribute a parser asks for is
// checked (number, range, unit hint) and remembered, so finish() can name the attributes nobody
// asked for, with the nearest valid name; children() does the same for child elements.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "scene/diagnostics.hpp"

namespace tinyxml2 {
class XMLElement;
}

namespace sear {

// An inclusive (or, at its low end, exclusive) bound on a number; the text goes into error
// messages. Every number a project file gives has one: see scene/value_ranges.hpp for the table.
// NaN is in no range, and the parser refuses infinities before a range is asked.
struct Range {
  double min = 0;
  double max = 0;
  bool min_exclusive = false;
  const char* text = "";

  static Range between(double lo, double hi, const char* text) { return {lo, hi, false, text}; }
  // (lo, hi]: for sizes and masses that must not be zero.
  static Range above(double lo, double hi, const char* text) { return {lo, hi, true, text}; }
  bool contains(double v) const { return (min_exclusive ? v > min : v >= min) && v <= max; }
};

class ElementReader {
 public:
  ElementReader(const tinyxml2::XMLElement* element, std::string file, Diagnostics& diagnostics);

  const std::string& file() const { return file_; }
  int line() const;
  std::string name() const;
  void error(const std::string& message) const;

  bool has(const char* attribute);
  std::string text(const char* attribute, const std::string& fallback);
  std::optional<std::string> required_text(const char* attribute);
  // `unit` only explains the value in messages, e.g. "kg".
  double number(const char* attribute, double fallback, const Range& range, const char* unit = "");
  std::optional<double> required_number(const char* attribute, const Range& range, const char* unit = "");
  // A count or an index: a number in `range` with no fractional part.
  double whole_number(const char* attribute, double fallback, const Range& range);
  Eigen::Vector2d vec2(const char* attribute, const Eigen::Vector2d& fallback, const Range& each);
  Eigen::Vector3d vec3(const char* attribute, const Eigen::Vector3d& fallback, const Range& each);
  // One of `choices`; returns its index, or `fallback_index` when absent or wrong.
  std::size_t choice(const char* attribute, const std::vector<std::string>& choices, std::size_t fallback_index);
  // Whitespace-separated names.
  std::vector<std::string> names(const char* attribute);

  // Visits child elements; a child not in `allowed` is an error with a suggestion.
  void children(std::initializer_list<const char*> allowed,
                const std::function<void(const tinyxml2::XMLElement&)>& visit);
  void children(const std::vector<std::string>& allowed, const std::function<void(const tinyxml2::XMLElement&)>& visit);

  // Reports attributes present in the file that no read above asked for.
  void finish();

 private:
  std::optional<double> parse_number(const char* attribute, const char* value, const Range& range, const char* unit);
  template <int N>
  Eigen::Matrix<double, N, 1> vector(const char* attribute, const Eigen::Matrix<double, N, 1>& fallback,
                                     const Range& each, const char* shape);

  const tinyxml2::XMLElement* element_;
  std::string file_;
  Diagnostics& diagnostics_;
  std::vector<std::string> asked_;
};

}  // namespace sear
