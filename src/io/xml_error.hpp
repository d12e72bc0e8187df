// tinyxml2's parse errors in plain words, for the URDF and MJCF importers.
#pragma once

#include <linx/scene.hpp>

#include <string>

namespace tinyxml2 {
class XMLDocument;
}

namespace linx::io {

/// Parses `text` into `doc`; throws SceneError naming `file`, the line and what is wrong in plain
/// words (`line 3: not well-formed XML (an end tag does not match its start tag)`, `the file is
/// empty`), never tinyxml2's own error text. Refuses first what tinyxml2 would read wrongly:
/// character 0 (a NUL byte or "&#0;", naming the attribute it would cut short) and a <!DOCTYPE>
/// declaring entities (none is expanded).
void parseXml(tinyxml2::XMLDocument& doc, const std::string& text, const std::string& file);

}  // namespace linx::io
