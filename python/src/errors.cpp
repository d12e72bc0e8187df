#include "errors.hpp"

#include <linx/checkpoint.hpp>
#include <linx/scene.hpp>
#include <linx/world.hpp>

#include <initializer_list>
#include <utility>

namespace py = pybind11;

namespace linx::python {
namespace {

// The exception types, created once at import and kept for the interpreter's life.
struct Types {
  py::handle error, scene, checkpoint, closed, busy, fault, non_finite, bound, energy;
};
Types types;

py::handle newType(py::module_& m, const char* name, std::initializer_list<py::handle> bases,
                   const char* doc) {
  py::tuple base_tuple(bases.size());
  std::size_t i = 0;
  for (py::handle b : bases) base_tuple[i++] = py::reinterpret_borrow<py::object>(b);
  const std::string qualified = std::string("linx.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, base_tuple.ptr(), nullptr);
  if (type == nullptr) throw py::error_already_set();
  m.attr(name) = py::handle(type);  // the module keeps a reference as well as `types`
  return type;
}

// Raises `type(message)` with the given attributes set on the exception object.
void raise(py::handle type, const char* message,
           std::initializer_list<std::pair<const char*, py::object>> attributes = {}) {
  py::object exception = type(message);
  for (const auto& [name, value] : attributes) exception.attr(name) = value;
  PyErr_SetObject(type.ptr(), exception.ptr());
}

py::object bodyIndex(int body) {
  return body < 0 ? py::none() : py::object(py::int_(body));
}

void raiseFault(py::handle type, const StepFault& e,
                std::initializer_list<std::pair<const char*, py::object>> more = {}) {
  py::object exception = type(e.what());
  exception.attr("step") = py::int_(e.step());
  exception.attr("time") = py::float_(e.time());
  exception.attr("body") = bodyIndex(e.body());
  for (const auto& [name, value] : more) exception.attr(name) = value;
  PyErr_SetObject(type.ptr(), exception.ptr());
}

void translate(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const SceneError& e) {
    raise(types.scene, e.what(),
          {{"file", py::str(e.file())},
           {"field", py::str(e.field())},
           {"problem", py::str(e.problem())}});
  } catch (const CheckpointError& e) {
    raise(types.checkpoint, e.what());
  } catch (const NonFiniteState& e) {
    raiseFault(types.non_finite, e);
  } catch (const BoundExceeded& e) {
    raiseFault(types.bound, e, {{"joint", bodyIndex(e.joint())}});
  } catch (const EnergyGrowth& e) {
    raiseFault(types.energy, e,
               {{"produced", py::float_(e.produced())}, {"bound", py::float_(e.bound())}});
  } catch (const StepFault& e) {
    raiseFault(types.fault, e);
  } catch (const ClosedWorld& e) {
    raise(types.closed, e.what());
  } catch (const WorldBusy& e) {
    raise(types.busy, e.what());
  } catch (const RunFolderError& e) {  // a folder another recording or run is writing
    raise(types.error, e.what());
  }
  // Everything else: pybind11's own translation (invalid_argument -> ValueError, out_of_range
  // -> IndexError, runtime_error -> RuntimeError, bad_alloc -> MemoryError).
}

}  // namespace

void bindErrors(py::module_& m) {
  const py::handle exception = PyExc_Exception, value = PyExc_ValueError,
                   runtime = PyExc_RuntimeError;
  types.error = newType(m, "Error", {exception}, "Base of every error linx raises itself.");
  types.scene = newType(m, "SceneError", {types.error, value},
                        "A bad scene or model file, or a bad scene built in code. Attributes: "
                        "file, field (a path such as 'bodies[2].mass') and problem.");
  types.checkpoint = newType(
      m, "CheckpointError", {types.error, value},
      "A checkpoint or saved state that cannot be read: damaged, cut, or of another world.");
  types.closed = newType(m, "ClosedError", {types.error, value},
                         "A World (or a handle of one) used after World.close().");
  types.busy = newType(m, "BusyError", {types.error, runtime},
                       "A World used while another thread steps it.");
  types.fault =
      newType(m, "StepFault", {types.error, runtime},
              "A fault found by World.step() that makes its results meaningless "
              "(docs/solver.md, 'Faults'). Attributes: step, time, body (index or None).");
  types.non_finite = newType(m, "NonFiniteState", {types.fault},
                             "A body's state or a joint's rows stopped being finite.");
  types.bound = newType(m, "BoundExceeded", {types.fault},
                        "A body moved faster than the fault bounds allow, or a joint's error "
                        "passed its bound. Attribute joint: the joint's index or None.");
  types.energy = newType(m, "EnergyGrowth", {types.fault},
                         "Undriven steps made more energy than the fault settings allow. "
                         "Attributes produced and bound (J).");
  py::register_exception_translator(&translate);
}

}  // namespace linx::python
