// The compiled part of the linx Python package (python/linx/): linx._linx.
#include "bindings.hpp"
#include "errors.hpp"

#include <pybind11/pybind11.h>

PYBIND11_MODULE(_linx, m) {
  m.doc() = "linx: rigid multibody dynamics (the compiled core; use the linx package).";
  m.attr("__version__") = LINX_VERSION;
  linx::python::bindErrors(m);
  linx::python::bindWorld(m);
  linx::python::bindBatch(m);
  linx::python::bindCallCosts(m);
  linx::python::bindSchema(m);
}
