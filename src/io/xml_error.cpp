#include "io/xml_error.hpp"

#include <fmt/format.h>
#include <tinyxml2.h>

#include <algorithm>
#include <cstddef>
#include <string>
#include <string_view>

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

std::size_t lineAt(const std::string& text, std::size_t pos) {
  return 1 + static_cast<std::size_t>(
                 std::count(text.begin(), text.begin() + static_cast<long>(pos), '\n'));
}

// What holds the text at `pos`: "<include> file" inside a tag (the attribute before it), else
// "the text after <include>" (the tag before it).
std::string holderAt(const std::string& text, std::size_t pos) {
  const std::size_t lt = text.rfind('<', pos);
  if (lt == std::string::npos) return "the text before the first element";
  const std::size_t gt = text.rfind('>', pos);
  const std::size_t name_end = std::min(text.find_first_of(" \t\r\n/>", lt + 1), pos);
  const std::string_view tag = std::string_view(text).substr(lt + 1, name_end - lt - 1);
  if (gt != std::string::npos && gt > lt) return fmt::format("the text after <{}>", tag);
  const std::size_t eq = text.rfind('=', pos);
  if (eq == std::string::npos || eq < lt) return fmt::format("<{}>", tag);
  const std::size_t end = text.find_last_not_of(" \t\r\n", eq - 1) + 1;
  if (end <= lt + 1 + tag.size()) return fmt::format("<{}>", tag);
  const std::size_t begin = text.find_last_of(" \t\r\n", end - 1) + 1;
  return fmt::format("<{}> {}", tag, std::string_view(text).substr(begin, end - begin));
}

// A character reference "&#0;" or "&#x00;" at `pos` (to character 0), or 0.
std::size_t nulReferenceAt(const std::string& text, std::size_t pos) {
  if (text.compare(pos, 2, "&#") != 0) return 0;
  std::size_t i = pos + 2;
  if (i < text.size() && (text[i] == 'x' || text[i] == 'X')) ++i;
  const std::size_t digits = i;
  while (i < text.size() && text[i] == '0') ++i;
  return i > digits && i < text.size() && text[i] == ';' ? i + 1 - pos : 0;
}

// What tinyxml2 would read wrongly, refused before it parses: character 0 (a NUL byte ends its
// text there; "&#0;" cuts an attribute short, so that file="a.xml&#0;b" read as "a.xml"), and a
// <!DOCTYPE> declaring entities (tinyxml2 expands none: their references stay as written, and
// a "billion laughs" file read as a document without its elements). Comments are skipped.
void refuseUnreadable(const std::string& text, const std::string& file) {
  for (std::size_t pos = 0; pos < text.size(); ++pos) {
    if (text.compare(pos, 4, "<!--") == 0) {
      const std::size_t end = text.find("-->", pos + 4);
      if (end == std::string::npos) return;  // the parser names the unclosed comment
      pos = end + 2;
      continue;
    }
    const auto refuse = [&](const std::string& problem) {
      throw SceneError(file, fmt::format("line {}", lineAt(text, pos)), problem);
    };
    const auto cut = [&](const std::string& what) {
      refuse(fmt::format("{}: {}, which XML does not allow (it would cut the value short there)",
                         holderAt(text, pos), what));
    };
    if (text[pos] == '\0') cut("a NUL byte");
    if (const std::size_t n = nulReferenceAt(text, pos))
      cut(fmt::format("character 0 ('{}')", text.substr(pos, n)));
    if (text.compare(pos, 9, "<!DOCTYPE") == 0) {
      const std::size_t subset = text.find_first_of("[>", pos);
      if (subset != std::string::npos && text[subset] == '[')
        refuse(
            "a <!DOCTYPE> with declarations ([...]): linx reads no DTD and expands no entities "
            "(&name;); write their values out");
    }
  }
}

}  // namespace

void parseXml(tinyxml2::XMLDocument& doc, const std::string& text, const std::string& file) {
  refuseUnreadable(text, file);
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
