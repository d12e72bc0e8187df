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
  /// Reads every body's pose from the engine and updates the figure (a maximum over samples).
  void sample(const Engine& engine);
  /// Whether the runner should sample after `step` (1-based); the final step is always sampled.
  bool due(int step) const { return step % every_ == 0 || step == scene_.steps; }
  double value() const { return worst_; }
  /// "largest joint separation", ...
  static std::string describe(Metric metric);

 private:
  double jointSeparation(const std::vector<Pose>& poses) const;
  double displacement(const std::vector<Pose>& poses) const;
  double penetration(const std::vector<Pose>& poses) const;
  double pistonError(const std::vector<Pose>& poses) const;

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
};

}  // namespace bench
