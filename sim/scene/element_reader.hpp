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

// An inclusive or exclusive bound on a number; the text goes into error messages.
struct Range {
  double min = -1e300;
  double max = 1e300;
  bool min_exclusive = false;
  const char* text = "";

  static Range any() { return {}; }
  static Range positive() { return {0, 1e300, true, "> 0"}; }
  static Range non_negative() { return {0, 1e300, false, ">= 0"}; }
  static Range between(double lo, double hi, const char* text) { return {lo, hi, false, text}; }
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
  double number(const char* attribute, double fallback, Range range = Range::any(), const char* unit = "");
  std::optional<double> required_number(const char* attribute, Range range = Range::any(), const char* unit = "");
  Eigen::Vector2d vec2(const char* attribute, const Eigen::Vector2d& fallback);
  Eigen::Vector3d vec3(const char* attribute, const Eigen::Vector3d& fallback, Range each = Range::any());
  // One of `choices`; returns its index, or `fallback_index` when absent or wrong.
  std::size_t choice(const char* attribute, const std::vector<std::string>& choices, std::size_t fallback_index);
  // Whitespace-separated names.
  std::vector<std::string> names(const char* attribute);

  // Visits child elements; a child not in `allowed` is an error with a suggestion.
  void children(std::initializer_list<const char*> allowed,
                const std::function<void(const tinyxml2::XMLElement&)>& visit);

  // Reports attributes present in the file that no read above asked for.
  void finish();

 private:
  std::optional<double> parse_number(const char* attribute, const char* value, Range range, const char* unit);

  const tinyxml2::XMLElement* element_;
  std::string file_;
  Diagnostics& diagnostics_;
  std::vector<std::string> asked_;
};

}  // namespace sear
