// The Python exceptions of the linx module and the translation of the engine's C++ exceptions into
// them (docs/python.md, "Errors"): the same message, with the C++ exception's fields as attributes.
#pragma once

#include <pybind11/pybind11.h>

#include <stdexcept>
#include <string>

namespace linx::python {

/// Raised by a call on a World (or one of its handles) that close() ended.
class ClosedWorld : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Raised by a call on a World while another thread steps it (step() releases the GIL).
class WorldBusy : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Raised for a Body or Joint handle of another World than the one it was given to.
class ForeignHandle : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Creates linx.Error and its subclasses in `m` and registers the translator.
void bindErrors(pybind11::module_& m);

}  // namespace linx::python
