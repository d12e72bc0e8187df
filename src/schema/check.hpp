// The C++ API's checks of a described record (src/schema/describe.hpp): every field within its
// bounds, then the record's rules, as a scene file's are. A problem is a std::invalid_argument
// that starts with the field, as scene files name it: "motor.max_force: must be >= 0, got -1".
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "schema/describe.hpp"

namespace linx::schema {

void checkSignal(const Signal& s, const std::string& field);

template <class R>
void check(const R& record, const std::string& prefix = "");

class Check {
 public:
  explicit Check(std::string prefix) : prefix_(std::move(prefix)) {}

  void field(const double& x, const FieldInfo& info) const {
    if (std::isnan(x) || (std::isinf(x) && !info.infinite)) fail(info, "must be finite");
    if (!info.range.contains(x)) fail(info, info.range.problem(x));
  }
  void field(const int& x, const FieldInfo& info) const {
    if (!info.range.contains(x)) fail(info, info.range.problem(x, true));
  }
  void field(const bool&, const FieldInfo&) const {}
  void field(const Signal& s, const FieldInfo& info) const { checkSignal(s, path(info)); }
  void field(const std::optional<double>& x, const FieldInfo& info) const {
    if (!x) return;
    if (!std::isfinite(*x)) fail(info, "must be finite");
    field(*x, info);
  }
  void field(const std::optional<Vec3>& v, const FieldInfo& info) const {
    if (v && !v->allFinite()) fail(info, "must be a finite vector");
    if (v && info.direction && !(v->norm() > 0)) fail(info, "must not be zero");
  }
  void field(const std::optional<Signal>& s, const FieldInfo& info) const {
    if (s) checkSignal(*s, path(info));
  }
  template <class R>
  requires kIsRecord<R>
  void field(const std::optional<R>& r, const FieldInfo& info) const {
    if (r) check(*r, path(info) + ".");
  }
  template <class E>
  requires std::is_enum_v<E>
  void field(const E& e, const FieldInfo& info) const {
    if (static_cast<std::size_t>(e) >= info.choices.size()) fail(info, "not a known choice");
  }

 private:
  std::string path(const FieldInfo& info) const { return prefix_ + std::string(info.name); }
  [[noreturn]] void fail(const FieldInfo& info, const std::string& problem) const {
    throw std::invalid_argument(fmt::format("{}: {}", path(info), problem));
  }

  std::string prefix_;
};

/// Throws std::invalid_argument("PREFIX.FIELD: PROBLEM") for the first field out of its bounds,
/// or the first rule of the record broken.
template <class R>
void check(const R& record, const std::string& prefix) {
  Check visitor(prefix);
  describe(visitor, const_cast<R&>(record));  // the visitor only reads
  if constexpr (requires { rules(record); }) {
    if (const auto p = rules(record)) {
      const std::string field =
          p->field.empty() ? prefix.substr(0, prefix.size() - 1) : prefix + p->field;
      throw std::invalid_argument(field.empty() ? p->problem
                                                : fmt::format("{}: {}", field, p->problem));
    }
  }
}

}  // namespace linx::schema
