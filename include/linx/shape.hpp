// Collision and drawing geometry attached to a body in its local frame, with its material.
#pragma once

#include <linx/types.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace linx {

enum class ShapeType { Sphere, Box, Capsule, Cylinder, Plane, Convex, Mesh, Ellipsoid };

/// A shape in the body frame. Capsules and cylinders are along the local z axis; an ellipsoid's
/// semi-axes are along its local x, y and z. Planes and meshes
/// are static geometry: only a static body may carry them.
struct ShapeDef {
  ShapeType type = ShapeType::Sphere;
  double radius = 0.5;        ///< sphere, capsule, cylinder (m)
  Vec3 size = Vec3::Ones();   ///< box: full edge lengths (m)
  Vec3 radii = Vec3::Ones();  ///< ellipsoid: semi-axes along the shape's x, y, z (m)
  double length = 1.0;        ///< capsule (between cap centres), cylinder (m)
  Vec3 normal =
      Vec3::UnitZ();           ///< plane: unit normal in the shape frame, pointing out of the solid
  double offset = 0.0;         ///< plane: the points x with normal . x = offset (shape frame, m)
  std::vector<Vec3> points{};  ///< convex: the hull of these points; mesh: the vertices (m)
  std::vector<std::array<int, 3>> triangles{};  ///< mesh: vertex indices, counter-clockwise outside
  std::string file{};                   ///< mesh: the OBJ or STL file it was read from, if any
  Vec3 position = Vec3::Zero();         ///< offset from the centre of mass, body frame (m)
  Quat orientation = Quat::Identity();  ///< relative to the body frame

  // Material.
  std::optional<double> density{};  ///< (kg/m^3): gives the body's mass when it states none
  double friction = 0.5;            ///< Coulomb coefficient, >= 0 (combined per pair: sqrt(a b))
  double restitution = 0.0;         ///< in [0, 1] (combined per pair: max(a, b))

  // Collision filter: two shapes collide when (group1 & mask2) != 0 and (group2 & mask1) != 0.
  std::uint32_t group = 1;
  std::uint32_t mask = 0xffffffffu;
};

const char* shapeTypeName(ShapeType type);

/// True for shapes that only static bodies may carry (plane, mesh).
bool isStaticOnly(ShapeType type);

}  // namespace linx
