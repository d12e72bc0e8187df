#include "metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace bench {
namespace {

Vec3 toWorld(const Pose& p, const Vec3& local) {
  return p.position + p.orientation * local;
}
Vec3 toLocal(const Pose& p, const Vec3& world) {
  return p.orientation.conjugate() * (world - p.position);
}

// Distance from a point to a box (negative inside: minus the depth to the nearest face).
double boxSignedDistance(const Pose& box, const Vec3& half, const Vec3& world_point) {
  const Vec3 q = toLocal(box, world_point).cwiseAbs() - half;
  const double outside = q.cwiseMax(0.0).norm();
  return outside > 0.0 ? outside : q.maxCoeff();
}

}  // namespace

Accuracy::Accuracy(const Scene& scene) : scene_(scene) {
  const auto initial = [&](int i) {
    return i < 0 ? Pose{} : Pose{scene.bodies[i].position, scene.bodies[i].orientation};
  };
  for (const Joint& j : scene.joints) {
    const Pose p1 = initial(j.body1), p2 = initial(j.body2);
    joints_.push_back({j.body1, j.body2, toLocal(p1, j.anchor), toLocal(p2, j.anchor),
                       p1.orientation.conjugate() * j.axis, j.kind == Joint::Kind::Slider});
  }
  if (scene.metric == Metric::PistonError) {
    const Pose crank = initial(scene.slider_crank_crank);
    // The crank pin is the joint between crank and rod: the crank's other joint besides the
    // world hinge. It lies crank_radius from the centre.
    for (const Joint& j : scene.joints) {
      if ((j.body1 == scene.slider_crank_crank) != (j.body2 == scene.slider_crank_crank) &&
          j.body1 >= 0 && j.body2 >= 0) {
        crank_pin_ = toLocal(crank, j.anchor);
        break;
      }
    }
  }
  // Chains and mechanisms are cheap to measure every step; contact scenes every 5th step.
  every_ = scene.metric == Metric::MaxPenetration || scene.bodies.size() > 2000 ? 5 : 1;
  poses_.resize(scene.bodies.size());
}

std::string Accuracy::describe(Metric metric) {
  switch (metric) {
    case Metric::JointSeparation:
      return "largest joint separation";
    case Metric::MaxDisplacement:
      return "largest box displacement";
    case Metric::MaxPenetration:
      return "deepest penetration";
    case Metric::PistonError:
      return "piston error";
    case Metric::PathError:
      return "distance from the known path";
  }
  return "?";
}

void Accuracy::sample(const Engine& engine, double time) {
  bool finite = true;
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    poses_[i] = engine.pose(static_cast<int>(i));
    finite = finite && poses_[i].position.allFinite() && poses_[i].orientation.coeffs().allFinite();
  }
  if (!finite) {  // a blown-up engine: std::max would drop a NaN, so say it here
    worst_ = NAN;
    return;
  }
  double v = 0.0;
  switch (scene_.metric) {
    case Metric::JointSeparation:
      v = jointSeparation(poses_);
      joints_worst_ = std::max(joints_worst_, v);
      break;
    case Metric::MaxDisplacement:
      v = displacement(poses_);
      break;
    case Metric::MaxPenetration:
      v = penetration(poses_);
      break;
    case Metric::PistonError:
      v = pistonError(poses_);
      break;
    case Metric::PathError:
      v = pathError(poses_, time);
      joints_worst_ = std::max(joints_worst_, jointSeparation(poses_));
      break;
  }
  // NaN (a blown-up engine) must show, not vanish under std::max.
  worst_ = std::isnan(v) || std::isnan(worst_) ? NAN : std::max(worst_, v);
}

double Accuracy::jointSeparation(const std::vector<Pose>& poses) const {
  double worst = 0.0;
  for (const LocalJoint& j : joints_) {
    const Pose p1 = j.body1 < 0 ? Pose{} : poses[j.body1];
    const Pose p2 = j.body2 < 0 ? Pose{} : poses[j.body2];
    Vec3 d = toWorld(p2, j.anchor2) - toWorld(p1, j.anchor1);
    if (j.slider) {  // a slider's anchors may part along its axis, not across it
      const Vec3 axis = p1.orientation * j.axis1;
      d -= d.dot(axis) * axis;
    }
    worst = std::max(worst, d.norm());
  }
  return worst;
}

double Accuracy::displacement(const std::vector<Pose>& poses) const {
  double worst = 0.0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (scene_.bodies[i].is_static) continue;
    worst = std::max(worst, (poses[i].position - scene_.bodies[i].position).norm());
  }
  return worst;
}

// Spheres against spheres (a uniform grid), against static boxes and against the ground plane.
double Accuracy::penetration(const std::vector<Pose>& poses) const {
  double worst = 0.0, cell = 0.0;
  std::vector<int> spheres, boxes;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Body& b = scene_.bodies[i];
    if (b.shape.kind == Shape::Kind::Sphere) {
      spheres.push_back(static_cast<int>(i));
      cell = std::max(cell, 2.0 * b.shape.radius);
    } else if (b.is_static && b.shape.kind == Shape::Kind::Box) {
      boxes.push_back(static_cast<int>(i));
    }
  }
  if (spheres.empty()) return 0.0;
  const auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    return static_cast<std::uint64_t>(((x & 0x1fffff) << 42) | ((y & 0x1fffff) << 21) |
                                      (z & 0x1fffff));
  };
  const auto cellOf = [&](const Vec3& p) {
    return Eigen::Vector3<std::int64_t>(static_cast<std::int64_t>(std::floor(p.x() / cell)),
                                        static_cast<std::int64_t>(std::floor(p.y() / cell)),
                                        static_cast<std::int64_t>(std::floor(p.z() / cell)));
  };
  std::unordered_map<std::uint64_t, std::vector<int>> grid;
  grid.reserve(spheres.size());
  for (int i : spheres) {
    const auto c = cellOf(poses[i].position);
    grid[key(c.x(), c.y(), c.z())].push_back(i);
  }
  for (int i : spheres) {
    const Vec3& p = poses[i].position;
    const double r = scene_.bodies[i].shape.radius;
    const auto c = cellOf(p);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(key(c.x() + dx, c.y() + dy, c.z() + dz));
          if (it == grid.end()) continue;
          for (int k : it->second) {
            if (k <= i) continue;
            const double depth = r + scene_.bodies[k].shape.radius - (poses[k].position - p).norm();
            worst = std::max(worst, depth);
          }
        }
      }
    }
    for (int b : boxes) {
      worst =
          std::max(worst, r - boxSignedDistance(poses[b], scene_.bodies[b].shape.half_extents, p));
    }
    if (scene_.ground_z) worst = std::max(worst, r - (p.z() - *scene_.ground_z));
    if (!std::isfinite(p.squaredNorm())) return NAN;
  }
  return worst;
}

double Accuracy::pistonError(const std::vector<Pose>& poses) const {
  const Vec3 pin = toWorld(poses[scene_.slider_crank_crank], crank_pin_) - scene_.crank_centre;
  const double phi = std::atan2(pin.y(), pin.x());
  const double r = scene_.crank_radius, l = scene_.rod_length;
  const double expected =
      r * std::cos(phi) + std::sqrt(l * l - r * r * std::sin(phi) * std::sin(phi));
  const double actual = poses[scene_.slider_crank_piston].position.x() - scene_.crank_centre.x();
  return std::abs(actual - expected);
}

double Accuracy::pathError(const std::vector<Pose>& poses, double time) {
  const KnownPath& path = *scene_.path;
  const std::optional<Vec3> expected = path.at(time);
  if (!expected) return 0.0;
  ++path_points_;
  return (toWorld(poses[path.body], path.point) - *expected).norm();
}

Energy::Energy(const Scene& scene) : scene_(scene) {
  poses_.resize(scene.bodies.size());
  twists_.resize(scene.bodies.size());
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const Body& b = scene.bodies[i];
    poses_[i] = Pose{b.position, b.orientation};
    twists_[i] = Twist{b.velocity, b.angular_velocity};
  }
  start_ = total(scene, poses_, twists_, &exchanged_);
  last_ = highest_ = lowest_ = start_;
}

double Energy::total(const Scene& scene, const std::vector<Pose>& poses,
                     const std::vector<Twist>& twists, double* kinetic) {
  double e = 0.0, k = 0.0;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const Body& b = scene.bodies[i];
    if (b.is_static) continue;
    const Vec3 w = poses[i].orientation.normalized().conjugate() * twists[i].angular;  // body frame
    const double ki =
        0.5 * b.mass * twists[i].linear.squaredNorm() + 0.5 * w.dot(b.inertia.cwiseProduct(w));
    k += ki;
    e += ki - b.mass * scene.gravity.dot(poses[i].position);
  }
  if (kinetic) *kinetic = k;
  return e;
}

void Energy::sample(const Engine& engine) {
  if (!finite_) return;
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    poses_[i] = engine.pose(static_cast<int>(i));
    twists_[i] = engine.velocity(static_cast<int>(i));
  }
  double kinetic = 0.0;
  const double e = total(scene_, poses_, twists_, &kinetic);
  if (!std::isfinite(e)) {  // a blown-up engine, or no velocities: say so for good
    finite_ = false;
    return;
  }
  exchanged_ = std::max(exchanged_, kinetic);
  highest_ = std::max(highest_, e);
  lowest_ = std::min(lowest_, e);
  last_ = e;
}

double Energy::percent(double change) const {
  if (!finite_) return NAN;
  if (change == 0.0) return 0.0;
  return 100.0 * change / exchanged_;  // nothing exchanged but a change: +-inf
}

double Energy::rise() const {
  return percent(highest_ - start_);
}

double Energy::end() const {
  return percent(last_ - start_);
}

double Energy::drift() const {
  return percent(std::max(highest_ - start_, start_ - lowest_));
}

}  // namespace bench
