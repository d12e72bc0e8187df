// Axis-aligned bounding boxes in the world frame, the currency of the broadphase
// (DESIGN.md section 6: collision = broadphase -> narrowphase -> contacts). shapeAabb() gives the
// exact tight world box of each primitive so the broadphase reports as few false pairs as it can;
// callers that want to keep pairs across a step add a margin with expanded(). Units: metres.
#pragma once

#include <linx/shape.hpp>
#include <linx/types.hpp>

#include <algorithm>
#include <cmath>

namespace linx::collision {

/// A closed box [min, max] per axis. Touching boxes overlap (a resting contact has zero gap).
struct Aabb {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();

  /// The box around a centre with the given half extents.
  static Aabb fromCentre(const Vec3& centre, const Vec3& half) {
    return Aabb{centre - half, centre + half};
  }

  /// True when the closed boxes share at least one point (false if any coordinate is NaN).
  bool overlaps(const Aabb& other) const {
    return min.x() <= other.max.x() && other.min.x() <= max.x() && min.y() <= other.max.y() &&
           other.min.y() <= max.y() && min.z() <= other.max.z() && other.min.z() <= max.z();
  }

  /// True when the point lies in the closed box.
  bool contains(const Vec3& p) const {
    return (min.array() <= p.array()).all() && (p.array() <= max.array()).all();
  }

  /// The smallest box containing both.
  Aabb merged(const Aabb& other) const {
    return Aabb{min.cwiseMin(other.min), max.cwiseMax(other.max)};
  }
  /// Grow this box to contain the other.
  void merge(const Aabb& other) { *this = merged(other); }

  /// The box grown by a margin (m) on every side (negative shrinks).
  Aabb expanded(double margin) const {
    const Vec3 m = Vec3::Constant(margin);
    return Aabb{min - m, max + m};
  }

  Vec3 centre() const { return 0.5 * (min + max); }
  Vec3 extent() const { return max - min; }
};

/// The tight world AABB of a shape attached to a body at body_pose. The shape's position and
/// orientation are in the body frame; capsules and cylinders are along the shape's local z;
/// box size is full edge lengths. With R the shape-to-world rotation, the half extent along world
/// axis i is: sphere r; box sum_j |R_ij| s_j / 2; capsule |R_iz| L/2 + r; cylinder
/// |R_iz| L/2 + r sqrt(1 - R_iz^2) (the rim circle's extent along axis i). Hulls and meshes bound
/// their points; a plane is unbounded except below it when its normal is a world axis.
inline Aabb shapeAabb(const ShapeDef& shape, const Pose& body_pose) {
  const Vec3 centre = body_pose.toWorld(shape.position);
  const Mat3 R = (body_pose.orientation * shape.orientation).normalized().toRotationMatrix();
  const Vec3 axis_z = R.col(2).cwiseAbs();
  Vec3 half = Vec3::Zero();
  switch (shape.type) {
    case ShapeType::Sphere:
      half = Vec3::Constant(shape.radius);
      break;
    case ShapeType::Box:
      half = R.cwiseAbs() * (0.5 * shape.size);
      break;
    case ShapeType::Capsule:
      half = 0.5 * shape.length * axis_z + Vec3::Constant(shape.radius);
      break;
    case ShapeType::Ellipsoid:  // exact: the support of R diag(radii) along each world axis
      half = (R * shape.radii.cwiseAbs().asDiagonal()).rowwise().norm();
      break;
    case ShapeType::Cylinder:
      for (int i = 0; i < 3; ++i) {
        const double c = axis_z[i];
        half[i] = 0.5 * shape.length * c + shape.radius * std::sqrt(std::max(0.0, 1.0 - c * c));
      }
      break;
    case ShapeType::Plane: {
      // Unbounded, except below an axis-aligned plane: the half space n . x <= offset.
      Aabb box{Vec3::Constant(-kInfinity), Vec3::Constant(kInfinity)};
      const Vec3 n = (R * shape.normal).normalized();
      const double offset = shape.offset + n.dot(centre);
      for (int i = 0; i < 3; ++i) {
        if (n[i] == 1.0) box.max[i] = offset;
        if (n[i] == -1.0) box.min[i] = -offset;
      }
      return box;
    }
    case ShapeType::Convex:
    case ShapeType::Mesh: {
      if (shape.points.empty()) return Aabb::fromCentre(centre, Vec3::Zero());
      Aabb box{Vec3::Constant(kInfinity), Vec3::Constant(-kInfinity)};
      for (const Vec3& p : shape.points) {
        const Vec3 w = centre + R * p;
        box.min = box.min.cwiseMin(w);
        box.max = box.max.cwiseMax(w);
      }
      return box;
    }
  }
  return Aabb::fromCentre(centre, half);
}

}  // namespace linx::collision
