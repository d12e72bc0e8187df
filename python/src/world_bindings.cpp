// linx.World: loading, stepping, settings, state in memory and on disk, copies and pickling.
#include "bindings.hpp"
#include "errors.hpp"
#include "py_world.hpp"
#include "state_arrays.hpp"

#include <linx/bounds.hpp>
#include <linx/checkpoint.hpp>
#include <linx/import.hpp>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

namespace py = pybind11;

namespace linx::python {
namespace {

using WorldClass = py::class_<PyWorld, std::shared_ptr<PyWorld>>;

py::bytes stateBytes(const WorldState& state) {
  return py::bytes(reinterpret_cast<const char*>(state.bytes.data()), state.bytes.size());
}

WorldState stateOf(const py::bytes& bytes) {
  const std::string_view view = bytes;  // no copy
  WorldState state;
  state.bytes.resize(view.size());
  std::memcpy(state.bytes.data(), view.data(), view.size());
  return state;
}

std::shared_ptr<PyWorld> fromSceneAndState(const std::string& scene_text, const std::string& file,
                                           const WorldState& state) {
  auto w = std::make_shared<PyWorld>(parseScene(scene_text, file));
  w->world().restoreState(state);
  return w;
}

std::shared_ptr<PyWorld> copyOf(const PyWorld& self) {
  const WorldState state = self.world().saveState();
  auto w = std::make_shared<PyWorld>(self.currentScene());
  w->world().restoreState(state);
  return w;
}

/// A checkpoint file as a world (what `linx run --checkpoint-every` and World.save write).
std::shared_ptr<PyWorld> fromCheckpoint(const std::filesystem::path& path) {
  const RunCheckpoint checkpoint = readCheckpoint(path);
  return fromSceneAndState(checkpoint.scene,
                           checkpoint.source.empty() ? path.string() : checkpoint.source,
                           checkpoint.state);
}

std::shared_ptr<PyWorld> load(const std::filesystem::path& path, bool floating_base,
                              bool allow_outside_paths) {
  if (path.extension() == ".lxc") return fromCheckpoint(path);
  ImportOptions options;
  options.floating_base = floating_base;
  options.allow_outside_paths = allow_outside_paths;
  return std::make_shared<PyWorld>(loadModel(path, options));
}

void checkPositive(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw py::value_error(fmt::format("{}: must be a finite number > 0, got {}", what, value));
}

IntegratorType integratorType(const std::string& name) {
  for (const IntegratorType t :
       {IntegratorType::Auto, IntegratorType::Step, IntegratorType::Accurate})
    if (name == integratorTypeName(t)) return t;
  throw py::value_error(fmt::format(
      "integrator: unknown integrator '{}' (expected \"auto\", \"step\" or \"accurate\")", name));
}

}  // namespace

void bindWorld(py::module_& m) {
  WorldClass c(m, "World",
               "A simulated world: bodies, joints, contacts and the time step. Made by "
               "linx.load(), linx.loads() or linx.Scene.build(); its bodies and joints keep the "
               "order of the scene.");

  m.def("load", &load, py::arg("path"), py::kw_only(), py::arg("floating_base") = false,
        py::arg("allow_outside_paths") = false,
        "Builds the world of a scene file (.json), a URDF robot (.urdf), an MJCF model (.xml) or a "
        "checkpoint (.lxc: the world as it was when saved). floating_base: a URDF's root link is "
        "free instead of fixed. allow_outside_paths: files the model names may lie outside its "
        "folder. Raises linx.SceneError (file, field, problem) or linx.CheckpointError.");
  m.def(
      "loads",
      [](const std::string& text, const std::string& file) {
        return std::make_shared<PyWorld>(parseScene(text, file));
      },
      py::arg("text"), py::arg("file") = "<string>",
      "Builds the world of a scene given as JSON text (docs/scene-format.md); `file` names it in "
      "messages, and files the scene names are looked for beside it. Raises linx.SceneError.");

  c.def("step", &PyWorld::step, py::arg("n") = 1,
        "Advances n time steps (the GIL is released meanwhile; Ctrl-C stops at a step boundary). "
        "Raises linx.StepFault (NonFiniteState, BoundExceeded, EnergyGrowth) when the run must "
        "stop: the world keeps the state in which the fault was found.");
  c.def_property_readonly(
      "time", [](PyWorld& self) { return self.world().time(); }, "Simulated time (s).");
  c.def_property_readonly(
      "step_count", [](PyWorld& self) { return self.world().stepCount(); }, "Steps taken.");
  c.def_property(
      "timestep", [](PyWorld& self) { return self.world().settings().timestep; },
      [](PyWorld& self, double h) {
        checkPositive(h, "timestep");
        if (h < kMinTimestep)
          throw pybind11::value_error(
              fmt::format("timestep: {:g} s is below {:g} s (its square must be a normal number)",
                          h, kMinTimestep));
        self.world().settings().timestep = h;
      },
      "Length of a step (s).");
  c.def_property(
      "gravity",
      [](PyWorld& self) {
        const Vec3 g = self.world().settings().gravity;
        auto a = newArray({3});
        std::copy(g.data(), g.data() + 3, a.mutable_data());
        return readOnly(std::move(a));
      },
      [](PyWorld& self, py::handle g) {
        World& w = self.world();
        w.settings().gravity = vectorArgument(g, "gravity");
        for (const BodyId id : self.bodies()) w.wake(id);
      },
      "Gravity (m/s^2, world frame).");
  c.def_property_readonly(
      "body_count", [](PyWorld& self) { return self.world(), self.bodies().size(); },
      "Number of bodies.");
  c.def_property_readonly(
      "joint_count", [](PyWorld& self) { return self.world(), self.joints().size(); },
      "Number of joints (springs included).");
  c.def_property_readonly(
      "body_names",
      [](PyWorld& self) {
        const World& w = self.world();
        py::list names;
        for (const BodyId id : self.bodies()) names.append(w.body(id).name());
        return names;
      },
      "The bodies' names, in body order (the order of the rows of positions, ...).");
  c.def_property_readonly(
      "joint_names",
      [](PyWorld& self) {
        const World& w = self.world();
        py::list names;
        for (const JointId id : self.joints()) names.append(w.joint(id).name());
        return names;
      },
      "The joints' names, in joint order.");
  c.def_property_readonly(
      "warnings", [](PyWorld& self) { return self.world(), self.scene().warnings; },
      "What the scene or model file held that linx does not use, one line each.");
  c.def_property_readonly(
      "kinetic_energy", [](PyWorld& self) { return self.world().energy().kinetic; },
      "Kinetic energy of all bodies (J).");
  c.def_property_readonly(
      "potential_energy", [](PyWorld& self) { return self.world().energy().potential; },
      "Gravitational potential energy (J), zero at the origin.");
  c.def_property_readonly(
      "max_joint_error", [](PyWorld& self) { return self.world().maxJointError(); },
      "The largest position error over all joints (m or rad).");
  c.def_property_readonly(
      "faults",
      [](PyWorld& self) {
        const auto f = self.world().faults();
        return std::vector<std::string>(f.begin(), f.end());
      },
      "Faults passed over while fault stopping is off (messages, oldest first).");
  c.def_property(
      "stop_on_fault", [](PyWorld& self) { return self.world().settings().faults.stop; },
      [](PyWorld& self, bool stop) { self.world().settings().faults.stop = stop; },
      "True (the default): a fault raises linx.StepFault. False: it is kept in `faults` and the "
      "world steps on (a non-finite state still raises).");
  c.def_property(
      "threads", [](PyWorld& self) { return self.world().settings().threads; },
      [](PyWorld& self, int threads) {
        checkThreads(threads);
        self.world().settings().threads = threads;
      },
      "Worker threads of a step (0: one per core); results are the same to the bit.");
  c.def_property_readonly(
      "solver_report",
      [](PyWorld& self) {
        const SolverReport& r = self.world().lastReport();
        py::dict d;
        d["rows"] = r.rows;
        d["iterations"] = r.iterations;
        d["residual"] = r.residual;
        d["redundant_rows"] = r.redundant_rows;
        d["converged"] = r.converged;
        return d;
      },
      "The last step's solve: rows, iterations, residual (largest complementarity violation), "
      "redundant_rows, converged.");

  c.def_property(
      "integrator",
      [](PyWorld& self) {
        return std::string(integratorTypeName(self.world().settings().integrator.type));
      },
      [](PyWorld& self, const std::string& name) {
        self.world().settings().integrator.type = integratorType(name);
      },
      "The time integrator (docs/integrators.md): \"auto\" (the default), \"step\" or "
      "\"accurate\".");
  c.def_property(
      "integrator_tolerance",
      [](PyWorld& self) { return self.world().settings().integrator.tolerance; },
      [](PyWorld& self, double tolerance) {
        if (!(tolerance >= 1e-14 && tolerance <= 1e-2))
          throw py::value_error(fmt::format(
              "integrator_tolerance: must be between 1e-14 and 1e-2, got {}", tolerance));
        self.world().settings().integrator.tolerance = tolerance;
      },
      "The accurate integrator's local error bound per step (relative to the larger of 1 and "
      "each value's size).");
  c.def_property_readonly(
      "integrator_report",
      [](PyWorld& self) {
        const IntegratorReport& r = self.world().lastIntegratorReport();
        py::dict d;
        d["bodies"] = r.bodies;
        d["steps"] = r.steps;
        d["rejected"] = r.rejected;
        d["error"] = r.error;
        d["events"] = r.events;
        return d;
      },
      "What the accurate integrator did over the last step: bodies it moved (the others took the "
      "step), its accepted steps, the steps it refused, the largest joint error it projected "
      "away, the rows it switched (events: limits met or left, motors and friction locked or "
      "slipping).");

  c.def(
      "save_state", [](PyWorld& self) { return stateBytes(self.world().saveState()); },
      "The whole state between steps as bytes (World::saveState): restore_state() on this "
      "world, or on a world built from the same scene, continues bit for bit as this one would.");
  c.def(
      "restore_state",
      [](PyWorld& self, const py::bytes& state) { self.world().restoreState(stateOf(state)); },
      py::arg("state"),
      "Puts the world in a state save_state() returned. Raises ValueError for the state of "
      "another world or a damaged one; the world is then unchanged.");
  c.def(
      "save",
      [](PyWorld& self, const std::filesystem::path& path) {
        RunCheckpoint checkpoint;
        checkpoint.scene = writeSceneJson(self.currentScene());
        checkpoint.source = self.scene().file;
        // Not a run's: one "frame" (the state itself) of a run that ends here, without files.
        checkpoint.steps = std::max<std::int64_t>(1, self.world().stepCount());
        checkpoint.frames = 1;
        checkpoint.bodies = self.world().bodyCount();
        checkpoint.joints = self.world().jointCount();
        checkpoint.state = self.world().saveState();
        writeCheckpoint(path, checkpoint);
      },
      py::arg("path"),
      "Writes the world (its scene and state) to a checkpoint file (docs/reliability.md), whole "
      "or not at all; linx.load(path) reads it back to a world that continues bit for bit.");
  c.def(
      "scene_json", [](PyWorld& self) { return writeSceneJson(self.currentScene()); },
      "The world's scene as scene-file text (its current settings, drives and limits; the "
      "bodies as built). linx.loads() of it builds the same world at its start.");
  c.def("copy", &copyOf,
        "An independent copy: the same scene and the same state; both step on identically.");
  c.def("__copy__", &copyOf);
  c.def("__deepcopy__", [](const PyWorld& self, py::handle) { return copyOf(self); });
  c.def(py::pickle(
      [](const PyWorld& self) {
        return py::make_tuple(writeSceneJson(self.currentScene()), self.scene().file,
                              stateBytes(self.world().saveState()));
      },
      [](const py::tuple& t) {
        if (t.size() != 3) throw py::value_error("linx.World: not a pickled world");
        return fromSceneAndState(t[0].cast<std::string>(), t[1].cast<std::string>(),
                                 stateOf(t[2].cast<py::bytes>()));
      }));
  c.def("close", &PyWorld::close,
        "Frees the world. Any later use of it or of its handles raises linx.ClosedError.");
  c.def_property_readonly("closed", &PyWorld::closed, "Whether close() was called.");
  c.def("__enter__", [](std::shared_ptr<PyWorld> self) { return self; });
  c.def("__exit__", [](PyWorld& self, py::args) { self.close(); });
  c.def("__repr__", [](PyWorld& self) {
    if (self.closed()) return std::string("<linx.World (closed)>");
    const World& w = self.world();
    return fmt::format("<linx.World '{}': {} bodies, {} joints, t = {} s>", self.scene().file,
                       self.bodies().size(), self.joints().size(), w.time());
  });

  bindStateArrays(c);
  bindHandles(m, c);
  bindRecording(m, c);
}

}  // namespace linx::python
