// The interface of an engine that runs a model file as it is (bench/model_files.hpp): unlike an
// Engine (engine.hpp), which is built from a bench::Scene, a ModelEngine reads the file itself,
// with its engine's own reader, and steps it with the file's step, gravity and options, every
// control input at zero.
#pragma once

#include "scene.hpp"

#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench {

/// Thrown by a ModelVariant's factory when its engine refuses the file; what() is the engine's
/// own message.
class CannotLoad : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ModelEngine {
 public:
  virtual ~ModelEngine() = default;
  /// Advances by timestep(), the file's.
  virtual void step() = 0;
  /// The file's step (s).
  virtual double timestep() const = 0;
  /// The solver and the file's settings as this engine runs them, for the table.
  virtual std::string settings() const = 0;
  /// The bodies that move (every body not fixed to the world) and their total mass (kg), as the
  /// engine computed it from the file (inertials, or the geoms at their density).
  virtual int movingBodies() const = 0;
  virtual double movingMass() const = 0;
  /// The centre of mass of the body named `name` in the file, world frame (m), at the current
  /// state; NaN when the engine blew up. Throws std::runtime_error when there is no such body.
  virtual Vec3 centreOfMass(const std::string& name) const = 0;
  /// The name of the file's first body that moves (a case that names no body reports it).
  virtual std::string firstMovingBody() const = 0;
};

/// One engine as a row of the table, for model files.
struct ModelVariant {
  std::string engine;    ///< "linx", "MuJoCo"
  std::string settings;  ///< shown when the file is refused (else ModelEngine::settings())
  /// Loads the file; throws CannotLoad when the engine refuses it.
  std::function<std::unique_ptr<ModelEngine>(const std::filesystem::path&)> make;
  /// The linx row that the table's time ratios of the file are taken against.
  bool reference = false;
};

/// linx: its importer (linx::importMjcf), then linx::buildWorld, default solver settings.
std::vector<ModelVariant> linxModelVariants();
/// MuJoCo: mj_loadXML, mj_makeData, mj_step (none when MuJoCo was not found at configure time).
std::vector<ModelVariant> mujocoModelVariants();

}  // namespace bench
