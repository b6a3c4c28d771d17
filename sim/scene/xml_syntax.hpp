// Why a file is not well-formed XML, in plain words and at the line a person would edit: an element
// left open is named where it was opened, not where the parser noticed. Found with expat, whose
// errors are precise, when tinyxml2 (which builds the document we read) refuses the file.
#pragma once

#include <optional>
#include <string>

namespace sear {

struct XmlSyntaxError {
  int line = 0;  // 1-based; 0 for the file as a whole (empty)
  std::string message;
};

// The first place where `xml` (UTF-8, whatever its declaration says) is not well-formed, or
// nothing when it is.
std::optional<XmlSyntaxError> xml_syntax_error(const std::string& xml);

// The same in words for a tinyxml2 error code (tinyxml2::XMLError), for when expat found nothing
// wrong and tinyxml2 still refused the file.
std::string tinyxml2_error_words(int error_id);

}  // namespace sear
