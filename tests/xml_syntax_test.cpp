// Malformed XML is explained in plain words at the line a person edits (issue 22): an element left
// open where it was opened, an unfinished tag where it starts, a misspelt end tag where it is.
#include <gtest/gtest.h>

#include "project_text.hpp"
#include "scene/diagnostics.hpp"
#include "scene/project_loader.hpp"
#include "scene/xml_syntax.hpp"

namespace sear {
namespace {

using test::line_of;

struct Case {
  const char* xml;
  const char* written;  // the text on the line the message must name
  const char* message;
};

class XmlSyntax : public ::testing::TestWithParam<Case> {};

TEST_P(XmlSyntax, SaysWhatIsWrongWhereItIsWritten) {
  const Case& c = GetParam();
  const auto e = xml_syntax_error(c.xml);
  ASSERT_TRUE(e.has_value()) << c.xml;
  EXPECT_EQ(e->line, line_of(c.xml, c.written)) << e->message;
  EXPECT_EQ(e->message, c.message);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, XmlSyntax,
    ::testing::Values(
        // The case: tinyxml2 names line 3 by chance of how it unwinds; expat stops at line 6.
        Case{"<project name=\"broken\">\n  <run duration=\"2\"/>\n  <world step=\"0.001\">\n"
             "    <terrain type=\"flat\"/>\n  <robot file=\"r.xml\"/>\n</project>\n",
             "<world", "<world> is never closed: </project> on line 6 comes before its </world>"},
        Case{"<project>\n  <robot name=\"r\">\n    <chassis mass=\"1\"\n  </robot>\n</project>\n", "<chassis",
             "the tag <chassis is not finished: no '>' (or '/>') before the '<' on line 4"},
        Case{"<project>\n  <robot/>\n</projec>\n", "</projec>",
             "</projec> does not match <project> (open since line 1): a misspelt end tag?"},
        Case{"<project>\n  <robot name=\"r\">\n  <x a=\"1\"/>\n", "<robot",
             "<robot> is never closed: the file ends before its </robot>; nor is <project> from line 1"},
        Case{"<project>\n  <robot name=r/>\n</project>\n", "<robot",
             "unexpected 'r' in the tag <robot: an attribute is written name=\"value\", its value in quotes, and "
             "the tag ends with '>' or '/>'"},
        Case{"<project>\n  <robot name=\"r & co\"/>\n</project>\n", "<robot",
             "a bare '&': write it as &amp; (in text and in attribute values alike)"},
        Case{"<project>\n  <!-- a note\n</project>\n", "<!--", "this comment is never closed with -->"},
        Case{"<project>\n  <robot/>\n</project>\n<extra/>\n", "<extra",
             "something follows the root element's end: a file holds one root element"}));

TEST(XmlSyntaxWhole, AnEmptyFileIsTheWholeFile) {
  const auto e = xml_syntax_error("");
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->line, 0);
  EXPECT_EQ(e->message, "the file holds no element (it is empty, or only comments)");
}

TEST(XmlSyntaxWhole, WellFormedIsNothing) {
  EXPECT_FALSE(xml_syntax_error("<project>\n  <robot name=\"r\"/>\n</project>\n").has_value());
  // Read as UTF-8 whatever the declaration says, as the loader reads it: "é" is two UTF-8 bytes.
  EXPECT_FALSE(xml_syntax_error("<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n<project name=\"\xC3\xA9\"/>\n")
                   .has_value());
}

// Through the loader: the message is ours, at the open element's line, with no tinyxml2 text.
TEST(XmlSyntaxWhole, TheLoaderSaysItInItsOwnWords) {
  const std::string xml =
      "<project name=\"broken\">\n  <world step=\"0.001\">\n    <terrain type=\"flat\"/>\n</project>\n";
  Diagnostics diagnostics;
  EXPECT_FALSE(load_project_text(xml, "broken.xml", diagnostics).has_value());
  ASSERT_EQ(diagnostics.all().size(), 1u) << diagnostics.joined();
  EXPECT_EQ(diagnostics.all()[0].str(),
            "broken.xml:2: error: malformed XML: <world> is never closed: </project> on line 4 comes before its </world>");
}

}  // namespace
}  // namespace sear
