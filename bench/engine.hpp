// The interface every engine adapter implements. An adapter builds a Scene once, then steps it;
// the runner times step() alone and reads poses between steps for the accuracy figures.
#pragma once

#include "scene.hpp"

#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench {

/// Thrown by a factory for a scene the engine variant does not run (too large for a dense
/// solver, a feature it lacks); what() says why, and the table prints it.
class Unsupported : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Pose {
  Vec3 position = Vec3::Zero();  ///< centre of mass, world frame (m)
  Quat orientation = Quat::Identity();
};

/// A body's velocity in the world frame: its centre of mass's and its angular velocity.
struct Twist {
  Vec3 linear = Vec3::Zero();   ///< centre of mass (m/s)
  Vec3 angular = Vec3::Zero();  ///< (rad/s)
};

class Engine {
 public:
  virtual ~Engine() = default;
  /// Advances the world by scene.timestep (one step, no substeps unless the settings say so).
  virtual void step() = 0;
  /// The pose of Scene::bodies[i] (static bodies included).
  virtual Pose pose(int i) const = 0;
  /// The velocity of Scene::bodies[i] at the pose that pose(i) reports (zero for static bodies).
  /// An adapter that cannot read it correctly keeps this default, NaN, and its energy figure
  /// (metrics.hpp) reads NaN rather than a wrong number.
  virtual Twist velocity(int /*i*/) const {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return Twist{Vec3::Constant(nan), Vec3::Constant(nan)};
  }
  /// Contact points of the last step, where the adapter can tell (for the memory figures).
  virtual std::size_t contactCount() const { return 0; }
};

/// One engine with one set of solver settings, as a row of the table.
struct Variant {
  std::string engine;    ///< "linx", "ODE", "Bullet", "MuJoCo", "DART"
  std::string settings;  ///< "QuickStep, 20 iterations", "btMultiBody", ...
  /// Builds the scene; throws Unsupported when this variant does not run it.
  std::function<std::unique_ptr<Engine>(const Scene&)> make;
  /// The linx row that the table's time ratios of this scene are taken against.
  bool reference = false;
  /// Worker threads (linx): a row with more than one is checked against its one-thread row for
  /// identical results and its speed-up.
  int threads = 1;
  /// That one-thread row's settings (empty: the reference row).
  std::string one_thread = {};
  /// The Pareto table's short label (--pareto): the solver, and the setting its count sweeps.
  std::string knob = {};
};

/// Variants of each engine compiled into this build. The peers' functions exist only when their
/// Debian package was found at configure time (LINX_BENCH_HAVE_ODE and so on).
std::vector<Variant> linxVariants(const Scene& scene);
std::vector<Variant> odeVariants(const Scene& scene);
std::vector<Variant> bulletVariants(const Scene& scene);
std::vector<Variant> mujocoVariants(const Scene& scene);
std::vector<Variant> dartVariants(const Scene& scene);

/// The Pareto table's rows of each engine (linx-bench --pareto): the variant of the main table
/// that has a count to sweep, made by the same factory at each of `counts`, and the engine's
/// default row when that is another solver. linx: its default row and the soft step at `counts`
/// substeps; ODE: dWorldQuickStep at `counts` iterations; Bullet: the sequential-impulse solver
/// at `counts` iterations; MuJoCo: its default (Newton) row and PGS at `counts` iterations; DART:
/// its default (Dantzig) row and PGS as its boxed-LCP solver at `counts` iterations.
std::vector<Variant> linxSweep(const Scene& scene, const std::vector<int>& counts);
std::vector<Variant> odeSweep(const Scene& scene, const std::vector<int>& counts);
std::vector<Variant> bulletSweep(const Scene& scene, const std::vector<int>& counts);
std::vector<Variant> mujocoSweep(const Scene& scene, const std::vector<int>& counts);
std::vector<Variant> dartSweep(const Scene& scene, const std::vector<int>& counts);

/// The integrator table's rows of each engine (linx-bench --integrators): linx's step and its
/// accurate integrator at tolerances 1e-6 to 1e-12; MuJoCo's Euler, implicit and RK4 integrators
/// at h and smaller steps; ODE's dWorldStep at h and h / 16. Each row's Variant::knob is its short
/// label.
std::vector<Variant> linxIntegrators(const Scene& scene);
std::vector<Variant> odeIntegrators(const Scene& scene);
std::vector<Variant> mujocoIntegrators(const Scene& scene);
/// Simbody (only here: the integrator table's mechanisms): its error-controlled integrators at
/// several accuracies, in internal coordinates, loops closed by constraints.
std::vector<Variant> simbodyIntegrators(const Scene& scene);

}  // namespace bench
