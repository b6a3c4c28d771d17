#include "scene/element_reader.hpp"

#include <fmt/format.h>
#include <tinyxml2.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "scene/nearest_name.hpp"

namespace sear {

ElementReader::ElementReader(const tinyxml2::XMLElement* element, std::string file, Diagnostics& diagnostics)
    : element_(element), file_(std::move(file)), diagnostics_(diagnostics) {}

int ElementReader::line() const { return element_->GetLineNum(); }
std::string ElementReader::name() const { return element_->Name(); }

void ElementReader::error(const std::string& message) const { diagnostics_.error(file_, line(), message); }

bool ElementReader::has(const char* attribute) {
  asked_.emplace_back(attribute);
  return element_->Attribute(attribute) != nullptr;
}

std::string ElementReader::text(const char* attribute, const std::string& fallback) {
  asked_.emplace_back(attribute);
  const char* v = element_->Attribute(attribute);
  return v ? std::string(v) : fallback;
}

std::optional<std::string> ElementReader::required_text(const char* attribute) {
  asked_.emplace_back(attribute);
  const char* v = element_->Attribute(attribute);
  if (!v || !*v) {
    error(fmt::format("<{}> needs attribute '{}'", name(), attribute));
    return std::nullopt;
  }
  return std::string(v);
}

std::optional<double> ElementReader::parse_number(const char* attribute, const char* value, const Range& range,
                                                  const char* unit) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(value, &end);
  while (end && *end == ' ') ++end;
  const std::string unit_text = *unit ? fmt::format(" {}", unit) : "";
  // strtod also reads "nan", "inf" and hex floats; a value beyond double's range sets ERANGE.
  // None of them is a measurement, and NaN would pass every range test below.
  if (end == value || (end && *end) || errno == ERANGE || !std::isfinite(v)) {
    error(fmt::format("<{}> attribute '{}': expected a number{}, got '{}'", name(), attribute,
                      *unit ? fmt::format(" ({})", unit) : "", value));
    return std::nullopt;
  }
  if (!range.contains(v)) {
    error(fmt::format("<{}> attribute '{}': {}{} is out of range (expected {})", name(), attribute, value, unit_text,
                      range.text));
    return std::nullopt;
  }
  return v;
}

double ElementReader::number(const char* attribute, double fallback, const Range& range, const char* unit) {
  asked_.emplace_back(attribute);
  const char* v = element_->Attribute(attribute);
  if (!v) return fallback;
  return parse_number(attribute, v, range, unit).value_or(fallback);
}

std::optional<double> ElementReader::required_number(const char* attribute, const Range& range, const char* unit) {
  asked_.emplace_back(attribute);
  const char* v = element_->Attribute(attribute);
  if (!v) {
    error(fmt::format("<{}> needs attribute '{}'{}", name(), attribute, *unit ? fmt::format(" ({})", unit) : ""));
    return std::nullopt;
  }
  return parse_number(attribute, v, range, unit);
}

double ElementReader::whole_number(const char* attribute, double fallback, const Range& range) {
  asked_.emplace_back(attribute);
  const char* v = element_->Attribute(attribute);
  if (!v) return fallback;
  const auto n = parse_number(attribute, v, range, "");
  if (!n) return fallback;
  if (*n != std::floor(*n)) {
    error(fmt::format("<{}> attribute '{}': expected a whole number in {}, got '{}'", name(), attribute, range.text, v));
    return fallback;
  }
  return *n;
}

namespace {

std::vector<std::string> split_words(const char* text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

}  // namespace

template <int N>
Eigen::Matrix<double, N, 1> ElementReader::vector(const char* attribute, const Eigen::Matrix<double, N, 1>& fallback,
                                                  const Range& each, const char* shape) {
  asked_.emplace_back(attribute);
  const char* v = element_->Attribute(attribute);
  if (!v) return fallback;
  const auto words = split_words(v);
  if (words.size() != static_cast<std::size_t>(N)) {
    error(fmt::format("<{}> attribute '{}': expected {}, got '{}'", name(), attribute, shape, v));
    return fallback;
  }
  Eigen::Matrix<double, N, 1> out = fallback;
  for (int i = 0; i < N; ++i) {
    auto n = parse_number(attribute, words[static_cast<std::size_t>(i)].c_str(), each, "");
    if (!n) return fallback;
    out[i] = *n;
  }
  return out;
}

Eigen::Vector2d ElementReader::vec2(const char* attribute, const Eigen::Vector2d& fallback, const Range& each) {
  return vector<2>(attribute, fallback, each, "two numbers 'x y'");
}

Eigen::Vector3d ElementReader::vec3(const char* attribute, const Eigen::Vector3d& fallback, const Range& each) {
  return vector<3>(attribute, fallback, each, "three numbers 'x y z'");
}

std::size_t ElementReader::choice(const char* attribute, const std::vector<std::string>& choices,
                                  std::size_t fallback_index) {
  asked_.emplace_back(attribute);
  const char* v = element_->Attribute(attribute);
  if (!v) return fallback_index;
  const auto it = std::find(choices.begin(), choices.end(), v);
  if (it != choices.end()) return static_cast<std::size_t>(it - choices.begin());
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
  error(fmt::format("<{}> attribute '{}': '{}' is not one of {}{}", name(), attribute, v, list,
                    did_you_mean(diagnostics_, v, choices)));
  return fallback_index;
}

std::vector<std::string> ElementReader::names(const char* attribute) {
  asked_.emplace_back(attribute);
  const char* v = element_->Attribute(attribute);
  return v ? split_words(v) : std::vector<std::string>{};
}

void ElementReader::children(std::initializer_list<const char*> allowed,
                             const std::function<void(const tinyxml2::XMLElement&)>& visit) {
  children(std::vector<std::string>(allowed.begin(), allowed.end()), visit);
}

void ElementReader::children(const std::vector<std::string>& allowed_names,
                             const std::function<void(const tinyxml2::XMLElement&)>& visit) {
  for (auto* child = element_->FirstChildElement(); child; child = child->NextSiblingElement()) {
    if (std::find(allowed_names.begin(), allowed_names.end(), child->Name()) == allowed_names.end()) {
      diagnostics_.error(file_, child->GetLineNum(),
                         fmt::format("unknown element <{}> in <{}>{}{}", child->Name(), name(),
                                     did_you_mean(diagnostics_, child->Name(), allowed_names),
                                     valid_names(diagnostics_, allowed_names, true)));
      continue;
    }
    visit(*child);
  }
}

void ElementReader::finish() {
  for (auto* a = element_->FirstAttribute(); a; a = a->Next()) {
    if (std::find(asked_.begin(), asked_.end(), a->Name()) != asked_.end()) continue;
    error(fmt::format("unknown attribute '{}' on <{}>{}{}", a->Name(), name(), did_you_mean(diagnostics_, a->Name(), asked_),
                      valid_names(diagnostics_, asked_)));
  }
}

}  // namespace sear
