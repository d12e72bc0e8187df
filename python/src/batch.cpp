// linx.Batch: many copies of one small world stepped together on all cores, their states as
// arrays of copies x bodies x 3 (learning, ensembles).
#include "bindings.hpp"
#include "py_world.hpp"
#include "state_arrays.hpp"

#include <pybind11/stl.h>

#include <fmt/format.h>
#include <omp.h>

#include <exception>
#include <memory>
#include <optional>

namespace py = pybind11;

namespace linx::python {
namespace {

class Batch {
 public:
  Batch(const PyWorld& prototype, int copies, int threads) : threads_(threads) {
    if (copies < 1) throw py::value_error(fmt::format("copies: must be >= 1, got {}", copies));
    checkThreads(threads);
    const Scene scene = prototype.currentScene();
    const WorldState state = prototype.world().saveState();
    for (int i = 0; i < copies; ++i) {
      auto w = std::make_shared<PyWorld>(scene);
      w->world().settings().threads = 1;  // the batch spreads the copies, not their steps
      w->world().restoreState(state);
      worlds_.push_back(std::move(w));
    }
    faults_.resize(worlds_.size());
  }

  /// A batch of these worlds (unpickling): they must be copies of one world.
  Batch(std::vector<std::shared_ptr<PyWorld>> worlds, int threads)
      : worlds_(std::move(worlds)), threads_(threads) {
    checkThreads(threads);
    if (worlds_.empty()) throw py::value_error("linx.Batch: no worlds");
    for (const auto& w : worlds_) {
      if (!w) throw py::value_error("linx.Batch: not a world");
      if (w->bodies().size() != worlds_.front()->bodies().size())
        throw py::value_error("linx.Batch: the worlds are not copies of one world");
    }
    faults_.resize(worlds_.size());
  }

  /// Steps every copy n times in parallel. A copy that faults stops there (the others go on);
  /// its message is kept in faults and the first copy's fault is raised once all are done.
  void step(long long n) {
    if (n < 0) throw py::value_error(fmt::format("step: n must be >= 0, got {}", n));
    std::vector<std::unique_ptr<PyWorld::Busy>> busy;
    std::vector<World*> worlds;
    for (auto& w : worlds_) {
      busy.push_back(std::make_unique<PyWorld::Busy>(*w));
      worlds.push_back(&w->worldWhileBusy());
    }
    std::vector<std::exception_ptr> errors(worlds.size());
    const int threads = threads_ > 0 ? threads_ : omp_get_num_procs();
    {
      py::gil_scoped_release release;
      const auto copies = static_cast<std::ptrdiff_t>(worlds.size());
#pragma omp parallel for num_threads(threads) schedule(dynamic)
      for (std::ptrdiff_t i = 0; i < copies; ++i) {
        try {
          World& w = *worlds[static_cast<std::size_t>(i)];
          for (long long s = 0; s < n; ++s) w.step();
        } catch (...) {
          errors[static_cast<std::size_t>(i)] = std::current_exception();
        }
      }
    }
    busy.clear();
    std::exception_ptr first;
    for (std::size_t i = 0; i < errors.size(); ++i) {
      if (!errors[i]) continue;
      try {
        std::rethrow_exception(errors[i]);
      } catch (const std::exception& e) {
        faults_[i] = fmt::format("copy {}: {}", i, e.what());
      }
      if (!first) first = errors[i];
    }
    if (first) std::rethrow_exception(first);
  }

  py::ssize_t bodies() const {
    return static_cast<py::ssize_t>(worlds_.front()->bodies().size());
  }
  py::ssize_t copies() const {
    return static_cast<py::ssize_t>(worlds_.size());
  }

  py::array_t<double> read(BodyField field) const {
    const int c = fieldColumns(field);
    auto a = newArray({copies(), bodies(), c});
    double* out = a.mutable_data();
    for (const auto& w : worlds_) {
      readBodies(w->world(), w->bodies(), field, out);
      out += bodies() * c;
    }
    return readOnly(std::move(a));
  }

  void write(BodyField field, py::handle value) {
    for (const auto& w : worlds_) w->world();  // none closed or busy
    const int c = fieldColumns(field);
    const auto a = arrayArgument(value, {copies(), bodies(), c}, fieldName(field));
    const double* rows = a.data();
    for (const auto& w : worlds_) {
      writeBodies(w->world(), w->bodies(), field, rows);
      rows += bodies() * c;
    }
  }

  std::vector<std::shared_ptr<PyWorld>> worlds_;
  std::vector<std::optional<std::string>> faults_;
  int threads_;
};

void bindField(py::class_<Batch>& c, BodyField field) {
  c.def_property(
      fieldName(field), [field](const Batch& b) { return b.read(field); },
      [field](Batch& b, py::handle value) { b.write(field, value); },
      fmt::format("World.{} of every copy: copies x bodies x {} (a copy of the data).",
                  fieldName(field), fieldColumns(field))
          .c_str());
}

}  // namespace

void bindBatch(py::module_& m) {
  py::class_<Batch> c(m, "Batch",
                      "Copies of one world stepped together on all cores (learning, ensembles): "
                      "each copy is a World of its own (batch[i]), with its drives and forces "
                      "set between steps; the state arrays gather all copies.");
  c.def(py::init([](const PyWorld& world, int copies, int threads) {
          return std::make_unique<Batch>(world, copies, threads);
        }),
        py::arg("world"), py::arg("copies"), py::kw_only(), py::arg("threads") = 0,
        "`copies` copies of `world` in its current state. threads: worker threads (0: one per "
        "core); each copy steps on one, so results are those of the world alone, to the bit.");
  c.def(py::pickle(
      [](const Batch& b) {
        for (const auto& w : b.worlds_) w->world();  // none closed or busy
        return py::make_tuple(b.threads_, b.worlds_);
      },
      [](const py::tuple& t) {
        if (t.size() != 2) throw py::value_error("linx.Batch: not a pickled batch");
        return std::make_unique<Batch>(t[1].cast<std::vector<std::shared_ptr<PyWorld>>>(),
                                       t[0].cast<int>());
      }));
  c.def("step", &Batch::step, py::arg("n") = 1,
        "Steps every copy n times. A copy that faults stops at its fault and the others go on; "
        "then the first fault is raised, and `faults` names every copy's.");
  c.def("__len__", &Batch::copies);
  c.def(
      "__getitem__",
      [](const Batch& b, const Index& given) {
        const long long n = static_cast<long long>(b.worlds_.size());
        long long i = given.value;
        if (i < 0) i = i < -n ? -1 : i + n;
        if (i < 0 || i >= n) throw py::index_error(fmt::format("copy {} of {}", given.text, n));
        return b.worlds_[static_cast<std::size_t>(i)];
      },
      "Copy i as a World (the same object each time).");
  c.def_property_readonly(
      "worlds", [](const Batch& b) { return b.worlds_; }, "Every copy, as Worlds.");
  c.def_property_readonly(
      "faults", [](const Batch& b) { return b.faults_; },
      "Per copy, the message of the fault that stopped it, or None.");
  c.def_property_readonly(
      "time",
      [](const Batch& b) {
        auto a = newArray({b.copies()});
        double* out = a.mutable_data();
        for (const auto& w : b.worlds_) *out++ = w->world().time();
        return readOnly(std::move(a));
      },
      "Each copy's time (s).");
  for (const BodyField f : {BodyField::Position, BodyField::Orientation, BodyField::LinearVelocity,
                            BodyField::AngularVelocity})
    bindField(c, f);
}

}  // namespace linx::python
