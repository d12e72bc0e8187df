// Collision and drawing geometry attached to a body in its local frame.
#pragma once

#include <linx/types.hpp>

namespace linx {

enum class ShapeType { Sphere, Box, Capsule, Cylinder };

/// A shape in the body frame. Capsules and cylinders are along the local z axis.
struct ShapeDef {
  ShapeType type = ShapeType::Sphere;
  double radius = 0.5;                  ///< sphere, capsule, cylinder (m)
  Vec3 size = Vec3::Ones();             ///< box: full edge lengths (m)
  double length = 1.0;                  ///< capsule (between cap centres), cylinder (m)
  Vec3 position = Vec3::Zero();         ///< offset from the centre of mass, body frame (m)
  Quat orientation = Quat::Identity();  ///< relative to the body frame
};

const char* shapeTypeName(ShapeType type);

}  // namespace linx
