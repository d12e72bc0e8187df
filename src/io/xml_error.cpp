#include "io/xml_error.hpp"

#include <fmt/format.h>
#include <tinyxml2.h>

namespace linx::io {
namespace {

const char* phrase(tinyxml2::XMLError error) {
  switch (error) {
    case tinyxml2::XML_ERROR_PARSING_ELEMENT:
      return "an element's tag is not closed";
    case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE:
      return "an attribute is not name=\"value\"";
    case tinyxml2::XML_ERROR_PARSING_TEXT:
      return "text where an element should be";
    case tinyxml2::XML_ERROR_PARSING_CDATA:
      return "a CDATA section is not closed";
    case tinyxml2::XML_ERROR_PARSING_COMMENT:
      return "a comment is not closed";
    case tinyxml2::XML_ERROR_PARSING_DECLARATION:
      return "a <?...?> declaration is not closed";
    case tinyxml2::XML_ERROR_PARSING_UNKNOWN:
      return "a <!...> construct is not closed";
    case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT:
      return "an end tag does not match its start tag";
    case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED:
      return "elements nested too deep";
    default:
      return "an element is not closed, or a stray '<' or '&'";
  }
}

}  // namespace

void parseXml(tinyxml2::XMLDocument& doc, const std::string& text, const std::string& file) {
  const tinyxml2::XMLError error = doc.Parse(text.data(), text.size());
  if (error == tinyxml2::XML_SUCCESS) return;
  if (error == tinyxml2::XML_ERROR_EMPTY_DOCUMENT)
    throw SceneError(file, "",
                     text.empty() ? "the file is empty" : "the file holds only white space");
  // Text before any markup: not XML at all ("hello"); otherwise XML with a fault.
  std::size_t start = text.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;  // a UTF-8 byte order mark
  start = text.find_first_not_of(" \t\r\n", start);
  const bool not_xml = start != std::string::npos && text[start] != '<';
  throw SceneError(file, fmt::format("line {}", doc.ErrorLineNum()),
                   not_xml ? "not XML (text where an element should be)"
                           : fmt::format("not well-formed XML ({})", phrase(error)));
}

}  // namespace linx::io
