// The benchmark's scenes, described once and independently of any engine. Every engine adapter
// (bench/engines/) builds the same bodies, shapes and joints from a Scene; the accuracy figures
// (bench/metrics.*) are computed from body poses alone, so no engine grades itself.
#pragma once

#include <Eigen/Geometry>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace bench {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

/// One collision shape per body, centred on the body's centre of mass and aligned with its
/// principal axes (the body frame).
struct Shape {
  enum class Kind { None, Sphere, Box, Capsule };
  Kind kind = Kind::None;
  double radius = 0.0;               ///< sphere, capsule (m)
  Vec3 half_extents = Vec3::Zero();  ///< box (m)
  double half_length = 0.0;          ///< capsule: half the segment, along the body's z axis (m)
};

struct Body {
  std::string name;
  double mass = 1.0;                     ///< (kg); ignored for static bodies
  Vec3 inertia = Vec3::Ones();           ///< principal moments about the centre of mass (kg m^2)
  Vec3 position = Vec3::Zero();          ///< centre of mass, world frame (m)
  Quat orientation = Quat::Identity();   ///< body frame relative to the world
  Vec3 velocity = Vec3::Zero();          ///< (m/s)
  Vec3 angular_velocity = Vec3::Zero();  ///< world frame (rad/s)
  bool is_static = false;                ///< never moves (container walls)
  Shape shape{};
};

/// Joint coordinates follow one convention in every adapter: a hinge angle is the rotation of
/// body2 relative to body1 about `axis`, zero at creation; a slider position is body2's
/// displacement relative to body1 along `axis`. Every scene's limits are symmetric about zero,
/// so a mistaken sign would not change the physics, only this statement.
struct Joint {
  enum class Kind { Hinge, Slider, Ball, Fixed };
  Kind kind = Kind::Hinge;
  int body1 = -1;              ///< index into Scene::bodies; -1 is the world
  int body2 = -1;              ///< index into Scene::bodies; -1 is the world
  Vec3 anchor = Vec3::Zero();  ///< world frame at creation (m)
  Vec3 axis = Vec3::UnitZ();   ///< world frame at creation, unit
  struct Limits {
    double lower = 0.0, upper = 0.0;  ///< (rad or m)
  };
  std::optional<Limits> limits = std::nullopt;
  struct Motor {
    double target_velocity = 0.0;  ///< (rad/s or m/s)
    double max_force = 0.0;        ///< (N m or N)
  };
  std::optional<Motor> motor = std::nullopt;
};

/// A spring and damper between a point of each of two bodies (-1: the world): its tension
/// stiffness (d - rest) + damping d' pulls the points together along the line between them, d
/// their distance.
struct Spring {
  int body1 = -1, body2 = -1;  ///< indices into Scene::bodies; -1 is the world
  Vec3 anchor1 = Vec3::Zero(), anchor2 = Vec3::Zero();  ///< the points, world frame at creation (m)
  double stiffness = 0.0;                               ///< (N/m)
  double damping = 0.0;                                 ///< (N s/m)
  double rest = 0.0;                                    ///< (m)
};

/// What "accuracy" means for a scene; see metrics.hpp.
enum class Metric {
  JointSeparation,  ///< largest distance between a joint's two anchor points (m)
  MaxDisplacement,  ///< largest displacement of any dynamic body from its start (m)
  MaxPenetration,   ///< deepest overlap of two shapes, or of a shape and a static one (m)
  PistonError,      ///< slider-crank: piston against r cos phi + sqrt(l^2 - r^2 sin^2 phi) (m)
  PathError,        ///< a point of a body against its known path (Scene::path) (m)
};

/// A point whose path is known independently of any engine (a closed form, published reference
/// positions): Metric::PathError is its largest distance from that path over the run.
struct KnownPath {
  int body = -1;              ///< index into Scene::bodies
  Vec3 point = Vec3::Zero();  ///< in the body's frame (m)
  std::string source;         ///< "closed form", "published reference solution", ...
  /// The point's position at time t (world frame, m), or nothing where the path is not known at t
  /// (published solutions give a few instants).
  std::function<std::optional<Vec3>(double t)> at;
};

struct Scene {
  std::string name;  ///< "chain", "heavy chain", "pyramid", "spheres", "slider-crank", "ragdolls"
  std::string size;  ///< "N=100", "base 20 (210 boxes)", ...
  double timestep = 1.0 / 60.0;  ///< (s)
  int steps = 0;
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
  double friction = 0.5;                          ///< Coulomb coefficient of every contact
  std::optional<double> ground_z = std::nullopt;  ///< an infinite plane z = ground_z, normal +z
  std::vector<Body> bodies;
  std::vector<Joint> joints;
  /// Only the integrator table's engines (linx, MuJoCo, Simbody, ODE) build them; the others
  /// refuse a scene that has any.
  std::vector<Spring> springs;
  Metric metric = Metric::JointSeparation;
  /// Whether the table shows the energy figure (metrics.hpp): set on scenes whose total energy,
  /// kinetic plus gravitational potential, stays constant in exact dynamics (no contacts, nothing
  /// driven or limited, no damping): the hinge chains.
  bool energy = false;
  /// Bodies joined by a joint never collide with each other (in every engine).
  int slider_crank_crank = -1, slider_crank_piston = -1;  ///< PistonError: body indices
  double crank_radius = 0.0, rod_length = 0.0;            ///< PistonError: r and l (m)
  Vec3 crank_centre = Vec3::Zero();                       ///< PistonError: crank hinge (m)
  std::optional<KnownPath> path = std::nullopt;           ///< PathError
};

}  // namespace bench
