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
/// empty`), never tinyxml2's own error text.
void parseXml(tinyxml2::XMLDocument& doc, const std::string& text, const std::string& file);

}  // namespace linx::io
