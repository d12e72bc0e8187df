// linx.schema(): the scene format's described records (linx/schema.hpp), as Python dicts: what
// each field of `solver`, `contact`, a joint's `motor`, ... is, its bounds, default and meaning.
#include "bindings.hpp"

#include <linx/schema.hpp>

#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>

namespace linx::python {

namespace py = pybind11;

namespace {

py::dict fieldDict(const schema::Field& f) {
  py::dict d;
  d["name"] = std::string(f.info.name);
  d["type"] = f.type;
  d["default"] = f.default_text;
  d["unit"] = std::string(f.info.unit);
  d["required"] = f.info.required;
  // Bounds as numbers (None where unbounded), and whether each end is open.
  const auto bound = [](double x) -> py::object {
    return std::isfinite(x) ? py::object(py::float_(x)) : py::object(py::none());
  };
  d["lower"] = bound(f.info.range.lower);
  d["upper"] = bound(f.info.range.upper);
  d["lower_open"] = f.info.range.lower_open;
  d["upper_open"] = f.info.range.upper_open;
  py::list aliases, choices;
  for (std::string_view a : f.info.aliases) aliases.append(std::string(a));
  for (std::string_view c : f.info.choices) choices.append(std::string(c));
  d["aliases"] = aliases;
  d["choices"] = choices;
  d["doc"] = std::string(f.info.doc);
  return d;
}

}  // namespace

void bindSchema(py::module_& m) {
  m.def(
      "schema",
      [](std::optional<std::string> record) -> py::object {
        const auto fields = [](const schema::Record& r) {
          py::list out;
          for (const schema::Field& f : r.fields) out.append(fieldDict(f));
          return out;
        };
        if (record) {
          const schema::Record* r = schema::findRecord(*record);
          if (!r) {
            std::string names;
            for (const schema::Record& known : schema::records())
              names += (names.empty() ? "" : ", ") + known.name;
            throw py::key_error("no record '" + *record + "' (records: " + names + ")");
          }
          return fields(*r);
        }
        py::dict all;
        for (const schema::Record& r : schema::records()) all[py::str(r.name)] = fields(r);
        return all;
      },
      py::arg("record") = py::none(),
      "The scene format's fields: schema() is a dict of every described record (solver, "
      "integrator, contact, sleep, faults, view, coordinate, limits, motor, spring) to its "
      "fields; schema('motor') the list of one. Each field is a dict: name, type, default, unit, "
      "required, lower, upper (None: unbounded), lower_open, upper_open, aliases (other engines' "
      "names for it), choices, doc. The same description the scene reader checks files against.");
}

}  // namespace linx::python
