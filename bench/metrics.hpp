// Accuracy figures computed from body poses alone, the same way for every engine.
#pragma once

#include "engine.hpp"
#include "scene.hpp"

#include <string>
#include <vector>

namespace bench {

class Accuracy {
 public:
  explicit Accuracy(const Scene& scene);
  /// Reads every body's pose from the engine at `time` (s; the known path's clock) and updates
  /// the figure (a maximum over samples).
  void sample(const Engine& engine, double time = 0.0);
  /// Whether the runner should sample after `step` (1-based); the final step is always sampled.
  bool due(int step) const { return step % every_ == 0 || step == scene_.steps; }
  double value() const { return worst_; }
  /// The largest joint separation (m) of a Metric::PathError or JointSeparation scene, and the
  /// number of samples the known path was compared at (a published solution's instants the run
  /// reached).
  double joints() const { return joints_worst_; }
  int pathPoints() const { return path_points_; }
  /// "largest joint separation", ...
  static std::string describe(Metric metric);

 private:
  double jointSeparation(const std::vector<Pose>& poses) const;
  double displacement(const std::vector<Pose>& poses) const;
  double penetration(const std::vector<Pose>& poses) const;
  double pistonError(const std::vector<Pose>& poses) const;
  double pathError(const std::vector<Pose>& poses, double time);

  const Scene& scene_;
  int every_ = 1;
  struct LocalJoint {
    int body1, body2;
    Vec3 anchor1, anchor2;  // in each body's frame (the world's for -1)
    Vec3 axis1;             // slider axis in body1's frame
    bool slider;
  };
  std::vector<LocalJoint> joints_;
  Vec3 crank_pin_ = Vec3::Zero();  // PistonError: crank pin in the crank's frame
  std::vector<Pose> poses_;
  double worst_ = 0.0;
  double joints_worst_ = 0.0;
  int path_points_ = 0;
};

/// The energy figure of a scene that conserves energy (Scene::energy): the total energy E, the
/// sum over dynamic bodies of 1/2 m v.v + 1/2 w.(R I R^T) w - m g.x (v the centre of mass's
/// velocity, w the angular velocity, R the orientation, I the body-frame principal inertia, x the
/// centre of mass, g the scene's gravity), against E0, its value in the scene's initial state.
/// Both figures are in percent of the energy exchanged, the largest kinetic energy seen (at the
/// start or at a sample): rise(), the largest E - E0 over the samples (the start included, so
/// never below zero), and end(), E - E0 at the last sample. A sample with a non-finite pose or
/// velocity (a blown-up engine, or an adapter that cannot read velocities) makes both NaN for good.
class Energy {
 public:
  explicit Energy(const Scene& scene);
  /// Reads every body's pose and velocity from the engine and updates the figures.
  void sample(const Engine& engine);
  double rise() const;
  double end() const;
  /// The largest |E - E0| over the samples, in percent of the energy exchanged (NaN as above).
  double drift() const;
  /// The total energy of the scene's dynamic bodies at the given poses and velocities (J);
  /// `kinetic`, when given, receives its kinetic part.
  static double total(const Scene& scene, const std::vector<Pose>& poses,
                      const std::vector<Twist>& twists, double* kinetic = nullptr);

 private:
  double percent(double change) const;

  const Scene& scene_;
  std::vector<Pose> poses_;
  std::vector<Twist> twists_;
  double start_ = 0.0, exchanged_ = 0.0, highest_ = 0.0, lowest_ = 0.0, last_ = 0.0;
  bool finite_ = true;
};

}  // namespace bench
