#include "py_world.hpp"

#include "arguments.hpp"
#include "errors.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <optional>
#include <utility>

namespace py = pybind11;

namespace linx::python {

PyWorld::PyWorld(Scene scene)
    : scene_(std::move(scene)), world_(std::make_unique<World>(buildWorld(scene_))) {
  bodies_ = world_->bodyIds();
  joints_ = world_->jointIds();
}

void PyWorld::check() const {
  if (world_ == nullptr) throw ClosedWorld("linx.World: the world is closed");
  if (busy_) throw WorldBusy("linx.World: another thread is stepping this world");
}

World& PyWorld::world() {
  check();
  return *world_;
}

const World& PyWorld::world() const {
  check();
  return *world_;
}

void PyWorld::close() {
  if (busy_) throw WorldBusy("linx.World: cannot close a world another thread is stepping");
  world_.reset();
}

PyWorld::Busy::Busy(PyWorld& owner) : owner_(owner) {
  owner.check();
  owner.busy_ = true;
}

void PyWorld::step(long long n) {
  if (n < 0) throw std::invalid_argument(fmt::format("step: n must be >= 0, got {}", n));
  Busy busy(*this);
  World& w = *world_;
  // Ctrl-C is noticed between chunks of steps: the world stops at a step boundary.
  constexpr long long kChunk = 256;
  for (long long done = 0; done < n;) {
    const long long chunk = std::min(kChunk, n - done);
    {
      py::gil_scoped_release release;
      for (long long i = 0; i < chunk; ++i) w.step();
    }
    done += chunk;
    if (done < n && PyErr_CheckSignals() != 0) throw py::error_already_set();
  }
}

Scene PyWorld::currentScene() const {
  const World& w = world();
  Scene scene = scene_;
  scene.settings = w.settings();
  const std::size_t joints = scene.joints.size(), springs = scene.springs.size();
  if (joints_.size() == joints + springs) {
    for (std::size_t i = 0; i < joints; ++i)
      scene.joints[i].def.coordinates = w.joint(joints_[i]).def().coordinates;
    for (std::size_t i = 0; i < springs; ++i)
      scene.springs[i].def.coordinates = w.joint(joints_[joints + i]).def().coordinates;
  }
  return scene;
}

namespace {

template <typename Handle, typename Id>
Id idOf(const std::shared_ptr<PyWorld>& owner, py::handle key, const std::vector<Id>& ids,
        const char* what, auto find) {
  if (py::isinstance<Handle>(key)) {
    const Handle& h = key.cast<const Handle&>();
    if (h.owner != owner)
      throw ForeignHandle(fmt::format("a {} handle of another linx.World", what));
    owner->world();  // closed or busy
    return h.id;
  }
  if (py::isinstance<py::str>(key)) {
    const std::string name = key.cast<std::string>();
    if (const auto id = find(owner->world(), name)) return *id;
    throw py::key_error(fmt::format("no {} named '{}'", what, name));
  }
  // Python ints and whatever stands for one (numpy's integers); not bools.
  if (const std::optional<Index> given = indexArgument(key)) {
    const long long n = static_cast<long long>(ids.size());
    // Clamped at the range of long long: adding n cannot overflow into the range.
    const long long i =
        given->value < 0 ? (given->value == LLONG_MIN ? -1 : given->value + n) : given->value;
    owner->world();
    if (i < 0 || i >= n)
      throw py::index_error(fmt::format("{} index {} out of range: the world has {} {}", what,
                                        given->text, n,
                                        what == std::string("body") ? "bodies" : "joints"));
    return ids[static_cast<std::size_t>(i)];
  }
  throw py::type_error(fmt::format("a {} is named by an int index, a str name or a handle, not {}",
                                   what, std::string(py::str(py::type::of(key).attr("__name__")))));
}

}  // namespace

BodyId bodyOf(const std::shared_ptr<PyWorld>& owner, py::handle key) {
  return idOf<BodyHandle>(owner, key, owner->bodies(), "body",
                          [](const World& w, const std::string& n) { return w.findBody(n); });
}

JointId jointOf(const std::shared_ptr<PyWorld>& owner, py::handle key) {
  return idOf<JointHandle>(owner, key, owner->joints(), "joint",
                           [](const World& w, const std::string& n) { return w.findJoint(n); });
}

}  // namespace linx::python
