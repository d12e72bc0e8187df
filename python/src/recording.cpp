// linx.Recording: a run folder written from Python (the CSV files and scene.json of `linx run`),
// which `linx render`, `linx view` and `linx plot` read (linx.render, linx.view).
#include "bindings.hpp"
#include "py_world.hpp"

#include <linx/recorder.hpp>
#include <linx/run_files.hpp>
#include <linx/scene.hpp>

#include <pybind11/stl/filesystem.h>

#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <optional>

namespace py = pybind11;

namespace linx::python {
namespace {

class Recording {
 public:
  Recording(std::shared_ptr<PyWorld> owner, const std::filesystem::path& dir, int every,
            bool contacts)
      : owner_(std::move(owner)), dir_(dir) {
    if (every < 1) throw py::value_error(fmt::format("every: must be >= 1, got {}", every));
    const Scene scene = owner_->currentScene();
    const World start = buildWorld(scene);  // the scene's bodies where the joints were made
    recorder_ = std::make_unique<Recorder>(dir, RecorderOptions{.contacts = contacts});
    recorder_->writeFile(std::string(run_files::kScene.name), runSceneJson(scene, start, every));
  }

  // One frame per time: a record() at the time of the last frame (no step since, as right after
  // World.record, which wrote the state then) writes nothing.
  void record() {
    Recorder& recorder = open();
    const World& world = owner_->world();
    if (last_time_ && *last_time_ == world.time()) return;
    recorder.record(world);
    last_time_ = world.time();
  }
  void close() {
    if (recorder_) recorder_->finish();
    recorder_.reset();
  }
  std::filesystem::path dir() const { return dir_; }

 private:
  Recorder& open() {
    if (!recorder_) throw py::value_error("linx.Recording: the recording is closed");
    return *recorder_;
  }

  std::shared_ptr<PyWorld> owner_;
  std::unique_ptr<Recorder> recorder_;
  std::filesystem::path dir_;
  std::optional<double> last_time_;  // of the last frame written
};

}  // namespace

void bindRecording(py::module_& m, py::class_<PyWorld, std::shared_ptr<PyWorld>>& world) {
  py::class_<Recording>(m, "Recording",
                        "A run folder being written (World.record): call record() after the "
                        "steps to keep, close() at the end (or use it in a with block).")
      .def("record", &Recording::record,
           "Appends the world's current state as a frame (bodies.csv, joints.csv, world.csv); "
           "at the time of the last frame (no step since) it writes nothing: one frame per "
           "time.")
      .def("close", &Recording::close, "Forces the files to disk and closes them.")
      .def_property_readonly("dir", &Recording::dir, "The run folder.")
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](Recording& r, py::args) { r.close(); });
  world.def(
      "record",
      [](std::shared_ptr<PyWorld> self, const std::filesystem::path& dir, int every,
         bool contacts) {
        auto r = std::make_unique<Recording>(self, dir, every, contacts);
        r->record();  // the first frame: the state now
        return r;
      },
      py::arg("dir"), py::kw_only(), py::arg("every") = 1, py::arg("contacts") = false,
      "Starts a run folder in `dir` (as `linx run --out` writes it: earlier run files there are "
      "removed) with the current state as its first frame; `every` is the steps between the "
      "frames you will record (it sets the viewer's playback). The recording holds the folder's "
      "lock until close(): a folder another recording or run is writing raises linx.Error. "
      "linx.render() and linx.view() take the folder.");
}

}  // namespace linx::python
