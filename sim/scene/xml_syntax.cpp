#include "scene/xml_syntax.hpp"

#include <expat.h>
#include <fmt/format.h>
#include <tinyxml2.h>

#include <algorithm>
#include <climits>
#include <memory>
#include <vector>

namespace sear {
namespace {

struct OpenElement {
  std::string name;
  int line = 0;
};

// The elements open at the point expat stopped, outermost first.
struct Walk {
  XML_Parser parser = nullptr;
  std::vector<OpenElement> open;
};

void XMLCALL on_start(void* data, const XML_Char* name, const XML_Char**) {
  auto* walk = static_cast<Walk*>(data);
  walk->open.push_back({name, static_cast<int>(XML_GetCurrentLineNumber(walk->parser))});
}

void XMLCALL on_end(void* data, const XML_Char*) {
  auto* walk = static_cast<Walk*>(data);
  if (!walk->open.empty()) walk->open.pop_back();
}

int line_at(const std::string& xml, std::size_t at) {
  return 1 + static_cast<int>(std::count(xml.begin(), xml.begin() + static_cast<std::ptrdiff_t>(std::min(at, xml.size())), '\n'));
}

// The name of the tag at `at`: "<name", "</name" or, as expat places a mismatched end tag, "/name".
std::string tag_name_at(const std::string& xml, std::size_t at) {
  std::size_t start = at;
  while (start < xml.size() && (xml[start] == '<' || xml[start] == '/')) ++start;
  std::size_t end = start;
  while (end < xml.size() && std::string(" \t\r\n/>").find(xml[end]) == std::string::npos) ++end;
  return xml.substr(start, end - start);
}

// A character expat would not take where it stands: what it is likely to mean. `at` is where it
// stopped, in bytes from the start.
XmlSyntaxError invalid_token(const std::string& xml, std::size_t at, int line) {
  const std::size_t tag_open = at == 0 ? std::string::npos : xml.rfind('<', at - 1);
  const std::size_t tag_close = at == 0 ? std::string::npos : xml.rfind('>', at - 1);
  const bool in_tag = tag_open != std::string::npos && (tag_close == std::string::npos || tag_close < tag_open);
  const char c = at < xml.size() ? xml[at] : '\0';
  if (c == '<' && in_tag) {
    // "<chassis mass="1"" and then the next tag: the first one never got its '>'.
    return {line_at(xml, tag_open),
            fmt::format("the tag <{} is not finished: no '>' (or '/>') before the '<' on line {}",
                        tag_name_at(xml, tag_open), line)};
  }
  if (c == '&' || (at > 0 && xml[at - 1] == '&'))
    return {line, "a bare '&': write it as &amp; (in text and in attribute values alike)"};
  if (in_tag)
    return {line, fmt::format("unexpected '{}' in the tag <{}: an attribute is written name=\"value\", its value in "
                              "quotes, and the tag ends with '>' or '/>'",
                              std::string(1, c), tag_name_at(xml, tag_open))};
  if (c == '<') return {line, "a '<' that starts no tag: in text write it as &lt;"};
  return {line, fmt::format("unexpected '{}' here", std::string(1, c))};
}

XmlSyntaxError unclosed_token(const std::string& xml, std::size_t at, int line) {
  const std::string rest = xml.substr(at, 9);
  if (rest.rfind("<!--", 0) == 0) return {line, "this comment is never closed with -->"};
  if (rest.rfind("<![CDATA[", 0) == 0) return {line, "this CDATA section is never closed with ]]>"};
  if (rest.rfind("<?", 0) == 0) return {line, "this <? ... ?> declaration is never closed with ?>"};
  if (rest.rfind("<", 0) == 0)
    return {line, fmt::format("the tag <{} is never finished with '>' before the file ends", tag_name_at(xml, at))};
  return {line, "the file ends in the middle of a tag or a value"};
}

}  // namespace

std::optional<XmlSyntaxError> xml_syntax_error(const std::string& xml) {
  // "UTF-8" over whatever the file's declaration says: the loader reads every file as UTF-8.
  const std::unique_ptr<XML_ParserStruct, void (*)(XML_Parser)> parser(XML_ParserCreate("UTF-8"), XML_ParserFree);
  if (!parser) return XmlSyntaxError{0, "out of memory while reading the XML"};
  Walk walk;
  walk.parser = parser.get();
  XML_SetUserData(parser.get(), &walk);
  XML_SetElementHandler(parser.get(), on_start, on_end);
  // expat takes an int length: a file beyond 2 GB goes in pieces.
  std::size_t done = 0;
  XML_Status status = XML_STATUS_OK;
  do {
    const std::size_t piece = std::min<std::size_t>(xml.size() - done, INT_MAX / 2);
    status = XML_Parse(parser.get(), xml.data() + done, static_cast<int>(piece), done + piece == xml.size());
    done += piece;
  } while (status == XML_STATUS_OK && done < xml.size());
  if (status == XML_STATUS_OK) return std::nullopt;

  const XML_Error code = XML_GetErrorCode(parser.get());
  const int line = static_cast<int>(XML_GetCurrentLineNumber(parser.get()));
  const XML_Index index = XML_GetCurrentByteIndex(parser.get());
  const std::size_t at = index < 0 ? xml.size() : static_cast<std::size_t>(index);
  switch (code) {
    case XML_ERROR_TAG_MISMATCH: {
      const std::string end = tag_name_at(xml, at);
      const auto outer = std::find_if(walk.open.begin(), walk.open.end(), [&](const OpenElement& e) { return e.name == end; });
      if (!walk.open.empty() && outer != walk.open.end()) {
        // </project> while <world> is open inside it: <world> was never closed.
        const OpenElement& inner = walk.open.back();
        return XmlSyntaxError{inner.line, fmt::format("<{}> is never closed: </{}> on line {} comes before its </{}>",
                                                      inner.name, end, line, inner.name)};
      }
      if (walk.open.empty()) return XmlSyntaxError{line, fmt::format("</{}> closes no open element", end)};
      const OpenElement& inner = walk.open.back();
      return XmlSyntaxError{line, fmt::format("</{}> does not match <{}> (open since line {}): a misspelt end tag?",
                                              end, inner.name, inner.line)};
    }
    case XML_ERROR_NO_ELEMENTS: {
      if (walk.open.empty()) return XmlSyntaxError{0, "the file holds no element (it is empty, or only comments)"};
      const OpenElement& inner = walk.open.back();
      std::string also;
      for (auto e = walk.open.rbegin() + 1; e != walk.open.rend(); ++e)
        also += fmt::format("{} <{}> from line {}", also.empty() ? "; nor is" : ",", e->name, e->line);
      return XmlSyntaxError{inner.line, fmt::format("<{}> is never closed: the file ends before its </{}>{}", inner.name,
                                                    inner.name, also)};
    }
    case XML_ERROR_INVALID_TOKEN: return invalid_token(xml, at, line);
    case XML_ERROR_UNCLOSED_TOKEN:
    case XML_ERROR_PARTIAL_CHAR: return unclosed_token(xml, at, line);
    case XML_ERROR_JUNK_AFTER_DOC_ELEMENT:
      return XmlSyntaxError{line, "something follows the root element's end: a file holds one root element"};
    case XML_ERROR_DUPLICATE_ATTRIBUTE:
      return XmlSyntaxError{line, fmt::format("the tag <{} gives an attribute twice", tag_name_at(xml, at))};
    case XML_ERROR_UNDEFINED_ENTITY:
      return XmlSyntaxError{line, "an unknown &name; entity: XML knows &lt; &gt; &amp; &quot; &apos; and &#NUMBER; "
                                  "(a bare '&' is written &amp;)"};
    case XML_ERROR_MISPLACED_XML_PI:
      return XmlSyntaxError{line, "<?xml ...?> may only be the very first text of the file"};
    case XML_ERROR_UNCLOSED_CDATA_SECTION: return XmlSyntaxError{line, "a CDATA section is never closed with ]]>"};
    default:
      return XmlSyntaxError{line, fmt::format("not well-formed XML ({})", XML_ErrorString(code))};
  }
}

std::string tinyxml2_error_words(int error_id) {
  switch (error_id) {
    case tinyxml2::XML_ERROR_PARSING_ELEMENT: return "an element's tag is not well-formed";
    case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE: return "an attribute is not written name=\"value\"";
    case tinyxml2::XML_ERROR_PARSING_TEXT: return "text that is not well-formed";
    case tinyxml2::XML_ERROR_PARSING_CDATA: return "a CDATA section that is not well-formed";
    case tinyxml2::XML_ERROR_PARSING_COMMENT: return "a comment that is not well-formed";
    case tinyxml2::XML_ERROR_PARSING_DECLARATION: return "a <?...?> declaration that is not well-formed";
    case tinyxml2::XML_ERROR_PARSING_UNKNOWN: return "a <!...> that is not well-formed";
    case tinyxml2::XML_ERROR_EMPTY_DOCUMENT: return "the file holds no element";
    case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT: return "an end tag does not match the element it closes";
    case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED: return "elements nested deeper than the reader takes";
    default: return "not well-formed XML";
  }
}

}  // namespace sear
