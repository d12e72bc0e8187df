// The object behind a Python linx.World: the engine's World, the scene it was built from (for
// copies, pickling and recordings), and the guards that keep Python from reaching a closed world
// or one another thread is stepping.
#pragma once

#include <linx/scene.hpp>
#include <linx/world.hpp>

#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

namespace linx::python {

class PyWorld {
 public:
  /// Builds the world of `scene` (buildWorld: throws SceneError).
  explicit PyWorld(Scene scene);

  /// The world; throws ClosedWorld after close(), WorldBusy while a step() runs in another thread.
  World& world();
  const World& world() const;
  bool closed() const { return world_ == nullptr; }
  /// The world without the checks, for the holder of a Busy guard (a batch stepping it).
  World& worldWhileBusy() { return *world_; }
  /// Frees the world; every later call raises linx.ClosedError. Throws WorldBusy while stepping.
  void close();

  /// Steps n times with the GIL released; the world is marked busy meanwhile.
  void step(long long n);

  /// The bodies and joints in order (a World made from Python never removes any).
  const std::vector<BodyId>& bodies() const { return bodies_; }
  const std::vector<JointId>& joints() const { return joints_; }

  /// The scene it was built from, with the world's current settings and joint coordinate
  /// definitions (motors, limits, springs, forces set since): buildWorld of it, then
  /// restoreState(saveState()), continues as this world would.
  Scene currentScene() const;
  const Scene& scene() const { return scene_; }

  /// Marks the world busy for the life of the guard (a step or a batch step). Throws WorldBusy if
  /// it already is, ClosedWorld if closed.
  class Busy {
   public:
    explicit Busy(PyWorld& owner);
    ~Busy() { owner_.busy_ = false; }
    Busy(const Busy&) = delete;
    Busy& operator=(const Busy&) = delete;

   private:
    PyWorld& owner_;
  };

 private:
  void check() const;

  Scene scene_;
  std::unique_ptr<World> world_;
  std::vector<BodyId> bodies_;
  std::vector<JointId> joints_;
  bool busy_ = false;  // read and written with the GIL held
};

/// A Body or Joint handle: its world and its id. Kept alive with the world's Python object.
struct BodyHandle {
  std::shared_ptr<PyWorld> owner;
  BodyId id;
};
struct JointHandle {
  std::shared_ptr<PyWorld> owner;
  JointId id;
};

/// The body (joint) that `key` names in `owner`: an index (negative from the end), a name, or a
/// handle of this world. Throws IndexError/KeyError for none, ValueError for a handle of another
/// world.
BodyId bodyOf(const std::shared_ptr<PyWorld>& owner, pybind11::handle key);
JointId jointOf(const std::shared_ptr<PyWorld>& owner, pybind11::handle key);

}  // namespace linx::python
