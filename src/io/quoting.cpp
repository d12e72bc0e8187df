#include "io/quoting.hpp"

#include <fmt/format.h>

#include <cstddef>
#include <optional>

namespace linx::io {

namespace {

struct CodePoint {
  char32_t value;
  std::size_t length;  // bytes
};

// The UTF-8 sequence at `at`, or nothing when the bytes there are not one (a stray continuation
// byte, a sequence cut short, an overlong form, a surrogate, or past U+10FFFF).
std::optional<CodePoint> decodeUtf8(std::string_view text, std::size_t at) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[at + i]); };
  const unsigned char lead = byte(0);
  std::size_t length = 0;
  char32_t value = 0;
  if (lead < 0x80) return CodePoint{lead, 1};
  if (lead >= 0xc2 && lead <= 0xdf) {
    length = 2;
    value = lead & 0x1f;
  } else if (lead >= 0xe0 && lead <= 0xef) {
    length = 3;
    value = lead & 0x0f;
  } else if (lead >= 0xf0 && lead <= 0xf4) {
    length = 4;
    value = lead & 0x07;
  } else {
    return std::nullopt;
  }
  if (at + length > text.size()) return std::nullopt;
  for (std::size_t i = 1; i < length; ++i) {
    if ((byte(i) & 0xc0) != 0x80) return std::nullopt;
    value = (value << 6) | (byte(i) & 0x3f);
  }
  constexpr char32_t kSmallest[] = {0, 0, 0x80, 0x800, 0x10000};
  if (value < kSmallest[length] || value > 0x10ffff || (value >= 0xd800 && value <= 0xdfff))
    return std::nullopt;
  return CodePoint{value, length};
}

// Code points that a terminal acts on or that change how the rest of a line reads.
bool invisible(char32_t c) {
  return (c >= 0x80 && c <= 0x9f) ||                   // C1 controls (CSI is U+009B)
         c == 0x061c || c == 0x200e || c == 0x200f ||  // bidirectional marks
         (c >= 0x2028 && c <= 0x202e) ||               // separators, embeddings, overrides
         (c >= 0x2066 && c <= 0x2069);                 // bidirectional isolates
}

// ASCII letters, digits and a few marks that no output language acts on inside a string.
bool plain(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
         std::string_view(" .,:;_-+=()/").find(c) != std::string_view::npos;
}

}  // namespace

std::string visible(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const std::optional<CodePoint> c = decodeUtf8(text, i);
    if (!c) {
      out += fmt::format("\\x{:02x}", static_cast<unsigned char>(text[i]));
      ++i;
      continue;
    }
    if (c->value == 0) {
      out += "\\0";
    } else if (c->value == '\n') {
      out += "\\n";
    } else if (c->value == '\r') {
      out += "\\r";
    } else if (c->value == '\t') {
      out += "\\t";
    } else if (c->value < 0x20 || c->value == 0x7f) {
      out += fmt::format("\\x{:02x}", static_cast<unsigned>(c->value));
    } else if (invisible(c->value)) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned>(c->value));
    } else {
      out.append(text.substr(i, c->length));
    }
    i += c->length;
  }
  return out;
}

std::string gnuplotString(std::string_view text) {
  std::string out = "\"";
  for (const char c : visible(text)) {
    if (plain(c))
      out += c;
    else
      out += fmt::format("\\{:03o}", static_cast<unsigned char>(c));
  }
  return out + '"';
}

std::string povComment(std::string_view text) {
  return visible(text);
}

std::string povString(std::string_view text) {
  std::string out = "\"";
  for (const char c : visible(text)) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + '"';
}

}  // namespace linx::io
