// The scene format's records described once (docs/scene-format.md): for every settings section
// and every part of a joint's coordinate, its fields in order, with their types, units, bounds,
// defaults and meaning. The scene reader and writer, the checks of the C++ API, Python's
// linx.schema() and the tables of docs/scene-format.md are all made from these descriptions
// (src/schema/), so a field is written in one place.
#pragma once

#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace linx::schema {

/// The values a number may take: [lower, upper], either end open, either end unbounded.
struct Range {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  bool lower_open = false;
  bool upper_open = false;

  static constexpr Range atLeast(double x) {
    return {x, std::numeric_limits<double>::infinity(), false, false};
  }
  static constexpr Range above(double x) {
    return {x, std::numeric_limits<double>::infinity(), true, false};
  }
  static constexpr Range closed(double a, double b) { return {a, b, false, false}; }
  static constexpr Range open(double a, double b) { return {a, b, true, true}; }

  bool contains(double x) const;
  /// ">= 0", "> 0", "in [0, 1]", "in (0, 2)"; empty for every number.
  std::string text() const;
  /// What is wrong with `x` outside the range: "must be >= 0, got -1", "must be between 0 and 1,
  /// got 2", "must be strictly between 0 and 2, got 2" ("an integer >= 1" for an integer field).
  std::string problem(double x, bool integer = false) const;
};

/// One field of a record as a scene file holds it.
struct FieldInfo {
  std::string_view name;
  std::string_view unit = {};  ///< "m/s", "rad", "m or rad" (a coordinate's); empty: none
  Range range = {};            ///< numbers: the values allowed
  std::string_view doc = {};   ///< the Meaning column of the docs' table
  /// Names other engines and formats use for it (`max_torque`, `effort`, `min`): a misspelt
  /// field that is one of these is pointed to this field.
  std::span<const std::string_view> aliases = {};
  /// Choices of a string field, in the order of its C++ enum.
  std::span<const std::string_view> choices = {};
  bool required = false;
  /// The docs' Default column where the C++ default does not say it ("none", "automatic").
  std::string_view default_text = {};
  /// A vector read as its direction: not zero, normalized.
  bool direction = false;
  /// An infinite value is allowed: no bound (a limit, a motor's max_force).
  bool infinite = false;
};

/// A described field with what the C++ side knows of it: its type and default as text.
struct Field {
  FieldInfo info;
  std::string type;          ///< "number >= 0", "boolean", "\"auto\", \"exact\" or \"pgs\"", ...
  std::string default_text;  ///< "`0.2`", "none", or empty for a required field
};

/// A record of the format: a settings section (`solver`) or a part of a joint (`motor`).
struct Record {
  std::string name;  ///< as the docs name it: "solver", "contact", "limits", "motor", ...
  std::vector<Field> fields;
};

/// Every described record, in the docs' order.
const std::vector<Record>& records();
/// The record named `name`, or nullptr.
const Record* findRecord(std::string_view name);
/// The record's table as docs/scene-format.md shows it: | Field | Type | Default | Meaning |.
std::string markdownTable(const Record& record);
/// `text` (a Markdown document) with the table between each `<!-- schema: NAME -->` line and the
/// next `<!-- /schema -->` line made anew from record NAME. Throws std::invalid_argument for an
/// unknown NAME or a marker left open.
std::string updateTables(std::string_view text);

}  // namespace linx::schema
