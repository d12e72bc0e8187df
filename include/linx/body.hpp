// A rigid body: mass properties, pose and velocity, applied loads. Every body keeps six degrees of
// freedom; joints restrict them through constraint rows.
#pragma once

#include <linx/shape.hpp>
#include <linx/signal.hpp>
#include <linx/types.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace linx {

/// Plain definition of a body, with defaults. All vectors are in the world frame at creation.
/// A dynamic body's mass properties come from what it gives (World::createBody completes them,
/// completeMassProperties in mass_properties.hpp):
/// - mass and inertia: as given;
/// - mass only: the inertia of its solid shapes filled uniformly to that mass, about `position`;
/// - neither: mass, centre of mass and inertia of its solid shapes at their densities; `position`
///   is then the shapes' origin and the body's centre of mass moves to the shapes' common centre.
/// A mass that the shapes' densities contradict, or an inertia without a mass, is refused.
struct BodyDef {
  std::string name;
  std::optional<double> mass = std::nullopt;   ///< (kg), > 0 unless the body is static
  std::optional<Mat3> inertia = std::nullopt;  ///< about the centre of mass, body frame (kg m^2)
  Vec3 position = Vec3::Zero();                ///< centre of mass, world frame (m)
  Quat orientation = Quat::Identity();         ///< body frame relative to the world
  Vec3 linear_velocity = Vec3::Zero();         ///< of the centre of mass, world frame (m/s)
  Vec3 angular_velocity = Vec3::Zero();        ///< world frame (rad/s)
  bool is_static = false;                      ///< infinite mass: never moves
  /// Infinite mass, moving at its own velocity (linear_velocity, angular_velocity; change it
  /// between steps with Body::setLinearVelocity): no force, joint or contact changes it, and it
  /// pushes and carries the dynamic bodies it touches (a conveyor, a lift, a moving platform). It
  /// needs no mass; not static as well.
  bool kinematic = false;
  /// A kinematic body's path: where its centre of mass is in time (m, world frame); each step takes
  /// it to the path's point at the step's end (its linear velocity is set to get there). It should
  /// start on the path's point at time 0.
  std::optional<VectorSignal> path = std::nullopt;
  /// Damping of the body's motion (1/s), >= 0: dv/dt = -linear_damping v, dw/dt = -angular_damping
  /// w, integrated implicitly (v / (1 + h c) each step: stable at any value). Air drag, or a body
  /// in a fluid, in a simple form; 0 (the default) for none.
  double linear_damping = 0.0;
  double angular_damping = 0.0;
  std::vector<ShapeDef> shapes;  ///< for drawing now and contacts later
};

/// A body of a World: its slot and the slot's generation. Index -1 stands for the fixed world
/// frame. A removed body's slot may be taken by a later body with the next generation, so an id
/// kept past World::removeBody refers to nothing (World::contains) instead of to the newcomer.
struct BodyId {
  int index = -1;
  std::uint32_t generation = 0;
  bool isWorld() const { return index < 0; }
  friend bool operator==(BodyId, BodyId) = default;
};
inline constexpr BodyId kWorldBody{};

class World;

class Body {
 public:
  explicit Body(const BodyDef& def);

  const std::string& name() const { return name_; }
  /// Its id in its world (World::createBody's).
  BodyId id() const { return id_; }
  bool isStatic() const { return is_static_; }
  bool isKinematic() const { return is_kinematic_; }
  /// Moved by forces, joints and contacts: neither static nor kinematic.
  bool isDynamic() const { return !is_static_ && !is_kinematic_; }

  double mass() const { return mass_; }
  double inverseMass() const { return inv_mass_; }
  const Mat3& inertiaBody() const { return inertia_body_; }  ///< (kg m^2), body frame
  const Mat3& inverseInertiaBody() const { return inv_inertia_body_; }
  Mat3 inertiaWorld() const;  ///< R I R^T (kg m^2)
  Mat3 inverseInertiaWorld() const;

  const Pose& pose() const { return pose_; }
  const Vec3& position() const { return pose_.position; }
  const Quat& orientation() const { return pose_.orientation; }
  const Vec3& linearVelocity() const { return v_; }
  const Vec3& angularVelocity() const { return w_; }
  void setPose(const Pose& pose);  ///< orientation is normalized
  void setLinearVelocity(const Vec3& v) { v_ = v; }
  void setAngularVelocity(const Vec3& w) { w_ = w; }

  /// Whether it has a velocity (linear or angular) at all.
  bool isMoving() const { return !v_.isZero(0.0) || !w_.isZero(0.0); }

  /// Velocity (m/s, world) of a point given in world coordinates, moving with the body.
  Vec3 velocityAt(const Vec3& world_point) const {
    return v_ + w_.cross(world_point - pose_.position);
  }

  /// Loads are accumulated until the end of the next step, then cleared. (N), (N m), world frame.
  void applyForce(const Vec3& force) { force_ += force; }
  void applyForceAtPoint(const Vec3& force, const Vec3& world_point);
  void applyTorque(const Vec3& torque) { torque_ += torque; }
  const Vec3& force() const { return force_; }
  const Vec3& torque() const { return torque_; }
  void clearLoads();

  /// 1/2 m v.v + 1/2 w.I w (J)
  double kineticEnergy() const;
  /// Angular momentum about the centre of mass, world frame (kg m^2/s).
  Vec3 angularMomentum() const { return inertiaWorld() * w_; }

  const std::vector<ShapeDef>& shapes() const { return shapes_; }

  double linearDamping() const { return linear_damping_; }  ///< (1/s), BodyDef::linear_damping
  double angularDamping() const { return angular_damping_; }

 private:
  friend class World;
  std::string name_;
  BodyId id_;
  bool is_static_ = false;
  bool is_kinematic_ = false;
  double mass_ = 0, inv_mass_ = 0;
  Mat3 inertia_body_, inv_inertia_body_;
  Pose pose_;
  Vec3 v_ = Vec3::Zero(), w_ = Vec3::Zero();
  Vec3 force_ = Vec3::Zero(), torque_ = Vec3::Zero();
  std::vector<ShapeDef> shapes_;
  double linear_damping_ = 0.0, angular_damping_ = 0.0;
};

}  // namespace linx
