// The parts of the linx Python module (module.cpp calls them in this order).
#pragma once

#include "py_world.hpp"

#include <pybind11/pybind11.h>

namespace linx::python {

void bindWorld(pybind11::module_& m);
void bindHandles(pybind11::module_& m, pybind11::class_<PyWorld, std::shared_ptr<PyWorld>>& world);
void bindRecording(pybind11::module_& m,
                   pybind11::class_<PyWorld, std::shared_ptr<PyWorld>>& world);
void bindBatch(pybind11::module_& m);
void bindCallCosts(pybind11::module_& m);
void bindSchema(pybind11::module_& m);

}  // namespace linx::python
