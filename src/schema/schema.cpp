// The public description of the scene format's records (linx/schema.hpp), collected from the
// describe() functions: each field's type and default read off its C++ member and the default
// record, and the tables of docs/scene-format.md made from them.
#include <linx/schema.hpp>

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <type_traits>

#include "schema/check.hpp"

namespace linx::schema {

bool Range::contains(double x) const {
  const bool above_lower = lower_open ? x > lower : x >= lower;
  const bool below_upper = upper_open ? x < upper : x <= upper;
  return above_lower && below_upper;
}

std::string Range::text() const {
  const bool bounded_below = std::isfinite(lower), bounded_above = std::isfinite(upper);
  if (bounded_below && bounded_above)
    return fmt::format("in {}{}, {}{}", lower_open ? '(' : '[', lower, upper,
                       upper_open ? ')' : ']');
  if (bounded_below) return fmt::format("{} {}", lower_open ? ">" : ">=", lower);
  if (bounded_above) return fmt::format("{} {}", upper_open ? "<" : "<=", upper);
  return {};
}

std::string Range::problem(double x, bool integer) const {
  const char* kind = integer ? "an integer " : "";
  const bool bounded_below = std::isfinite(lower), bounded_above = std::isfinite(upper);
  std::string bounds;
  if (bounded_below && bounded_above)
    bounds = lower_open || upper_open
                 ? fmt::format("{}strictly between {} and {}", kind, lower, upper)
                 : fmt::format("{}between {} and {}", kind, lower, upper);
  else
    bounds = fmt::format("{}{}", kind, text());
  return fmt::format("must be {}, got {}", bounds, x);
}

void checkSignal(const Signal& s, const std::string& field) {
  const auto bad = [&](const std::string& problem) {
    return std::invalid_argument(fmt::format("{}: {}", field, problem));
  };
  if (s.times.empty()) {
    if (s.values.size() != 1 || !std::isfinite(s.values[0])) throw bad("must be finite");
    return;
  }
  if (s.values.size() != s.times.size())
    throw bad(fmt::format("{} times but {} values", s.times.size(), s.values.size()));
  for (std::size_t i = 0; i < s.times.size(); ++i) {
    if (!std::isfinite(s.times[i])) throw bad(fmt::format("times[{}]: must be finite", i));
    if (!std::isfinite(s.values[i])) throw bad(fmt::format("values[{}]: must be finite", i));
    if (i > 0 && !(s.times[i] > s.times[i - 1]))
      throw bad(fmt::format("times[{}]: must be after times[{}] ({} <= {})", i, i - 1, s.times[i],
                            s.times[i - 1]));
  }
}

namespace {

std::string quotedChoices(std::span<const std::string_view> choices) {
  std::string out;
  for (std::size_t i = 0; i < choices.size(); ++i)
    out += fmt::format("{}`\"{}\"`",
                       i == 0                    ? ""
                       : i + 1 == choices.size() ? " or "
                                                 : ", ",
                       choices[i]);
  return out;
}

std::string withRange(std::string type, const Range& range) {
  const std::string bounds = range.text();
  return bounds.empty() ? type : fmt::format("{} {}", type, bounds);
}

// Fills a Record from a default-constructed struct: what each field is and holds by default.
class Collect {
 public:
  explicit Collect(Record& record) : record_(record) {}

  void field(double& x, const FieldInfo& info) {
    add(info, withRange("number", info.range), std::isfinite(x) ? fmt::format("`{}`", x) : "");
  }
  void field(int& x, const FieldInfo& info) {
    add(info, withRange("integer", info.range), fmt::format("`{}`", x));
  }
  void field(bool& x, const FieldInfo& info) { add(info, "boolean", fmt::format("`{}`", x)); }
  void field(Signal& s, const FieldInfo& info) {
    add(info, "number or table in time",
        s.times.empty() && s.values.size() == 1 ? fmt::format("`{}`", s.values[0]) : "");
  }
  void field(std::optional<double>&, const FieldInfo& info) {
    add(info, withRange("number", info.range), "none");
  }
  void field(std::optional<Vec3>&, const FieldInfo& info) {
    add(info, info.direction ? "non-zero vector" : "vector", "none");
  }
  void field(std::optional<Signal>&, const FieldInfo& info) {
    add(info, "number or table in time", "none");
  }
  template <class R>
  requires kIsRecord<R>
  void field(std::optional<R>&, const FieldInfo& info) {
    add(info, fmt::format("object ([below](#{}))", info.name), "none");
  }
  template <class E>
  requires std::is_enum_v<E>
  void field(E& e, const FieldInfo& info) {
    add(info, quotedChoices(info.choices),
        fmt::format("`\"{}\"`", info.choices[static_cast<std::size_t>(e)]));
  }

 private:
  void add(const FieldInfo& info, std::string type, std::string fallback) {
    std::string shown = info.required                ? std::string()
                        : !info.default_text.empty() ? std::string(info.default_text)
                                                     : std::move(fallback);
    if (info.required) type += ", **required**";
    record_.fields.push_back({info, std::move(type), std::move(shown)});
  }

  Record& record_;
};

template <class S>
Record collect(std::string name) {
  Record record{std::move(name), {}};
  S defaults{};
  Collect visitor(record);
  describe(visitor, defaults);
  return record;
}

}  // namespace

const std::vector<Record>& records() {
  static const std::vector<Record> all = {
      collect<SolverSettings>("solver"),    collect<IntegratorSettings>("integrator"),
      collect<ContactSettings>("contact"),  collect<SleepSettings>("sleep"),
      collect<FaultSettings>("faults"),     collect<SceneView>("view"),
      collect<CoordinateDef>("coordinate"), collect<JointLimits>("limits"),
      collect<JointMotor>("motor"),         collect<JointSpring>("spring"),
  };
  return all;
}

const Record* findRecord(std::string_view name) {
  for (const Record& r : records())
    if (r.name == name) return &r;
  return nullptr;
}

std::string markdownTable(const Record& record) {
  std::string out = "| Field | Type | Default | Meaning |\n|---|---|---|---|\n";
  for (const Field& f : record.fields) {
    const std::string meaning = f.info.unit.empty()
                                    ? std::string(f.info.doc)
                                    : fmt::format("({}) {}", f.info.unit, f.info.doc);
    out += fmt::format("| `{}` | {} | {} | {} |\n", f.info.name, f.type, f.default_text, meaning);
  }
  return out;
}

std::string updateTables(std::string_view text) {
  constexpr std::string_view kBegin = "<!-- schema: ", kEnd = "<!-- /schema -->";
  std::string out;
  std::size_t at = 0;
  while (true) {
    const std::size_t begin = text.find(kBegin, at);
    if (begin == std::string_view::npos) break;
    const std::size_t close = text.find(" -->\n", begin);
    if (close == std::string_view::npos)
      throw std::invalid_argument(
          fmt::format("offset {}: a schema marker not closed by ' -->'", begin));
    const std::string name(text.substr(begin + kBegin.size(), close - begin - kBegin.size()));
    const Record* record = findRecord(name);
    if (!record)
      throw std::invalid_argument(fmt::format("'{}': no such record of the schema", name));
    const std::size_t end = text.find(kEnd, close);
    if (end == std::string_view::npos)
      throw std::invalid_argument(fmt::format("'{}': no '{}' after its table", name, kEnd));
    out += text.substr(at, close + 5 - at);
    out += markdownTable(*record);
    at = end;
  }
  out += text.substr(at);
  return out;
}

}  // namespace linx::schema
