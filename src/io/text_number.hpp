// A number as linx reads it from a text file (an OBJ's or STL's coordinate, a CSV table's cell):
// a decimal in C's form (a sign, digits, a point, an exponent) and finite; not hex, inf or nan,
// which strtod would take, and nothing after it.
#pragma once

#include <charconv>
#include <cmath>
#include <optional>
#include <string_view>
#include <system_error>

namespace linx::io {

inline std::optional<double> finiteNumber(std::string_view word) {
  if (word.empty()) return std::nullopt;
  // from_chars takes no '+'.
  if (word.size() > 1 && word.front() == '+' && word[1] != '-' && word[1] != '+')
    word.remove_prefix(1);
  double value = 0.0;
  const char* end = word.data() + word.size();
  const auto [stop, error] = std::from_chars(word.data(), end, value, std::chars_format::general);
  if (error != std::errc{} || stop != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

}  // namespace linx::io
