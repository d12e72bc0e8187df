#include <linx/body.hpp>

#include <stdexcept>

namespace linx {

Body::Body(const BodyDef& def)
    : name_(def.name),
      is_static_(def.is_static),
      is_kinematic_(def.kinematic && !def.is_static),
      pose_{def.position, def.orientation.normalized()},
      v_(def.is_static ? Vec3::Zero() : def.linear_velocity),
      w_(def.is_static ? Vec3::Zero() : def.angular_velocity),
      shapes_(def.shapes),
      linear_damping_(def.linear_damping),
      angular_damping_(def.angular_damping) {
  if (is_static_ || is_kinematic_) {  // infinite mass
    mass_ = 0.0;
    inv_mass_ = 0.0;
    inertia_body_.setZero();
    inv_inertia_body_.setZero();
    return;
  }
  if (!def.mass || !def.inertia)
    throw std::invalid_argument(
        "Body: a dynamic body needs its mass and inertia (World::createBody completes them)");
  mass_ = *def.mass;
  inv_mass_ = 1.0 / mass_;
  // Symmetrize: a full tensor given with round-off asymmetry must still be a valid inertia.
  inertia_body_ = 0.5 * (*def.inertia + def.inertia->transpose());
  inv_inertia_body_ = inertia_body_.inverse();
}

Mat3 Body::inertiaWorld() const {
  const Mat3 r = pose_.orientation.toRotationMatrix();
  return r * inertia_body_ * r.transpose();
}

Mat3 Body::inverseInertiaWorld() const {
  const Mat3 r = pose_.orientation.toRotationMatrix();
  return r * inv_inertia_body_ * r.transpose();
}

void Body::setPose(const Pose& pose) {
  pose_.position = pose.position;
  pose_.orientation = pose.orientation.normalized();
}

void Body::applyForceAtPoint(const Vec3& force, const Vec3& world_point) {
  force_ += force;
  torque_ += (world_point - pose_.position).cross(force);
}

void Body::clearLoads() {
  force_.setZero();
  torque_.setZero();
}

double Body::kineticEnergy() const {
  if (is_static_) return 0.0;
  return 0.5 * mass_ * v_.squaredNorm() + 0.5 * w_.dot(inertiaWorld() * w_);
}

}  // namespace linx
