#include <linx/shape.hpp>

namespace linx {

const char* shapeTypeName(ShapeType type) {
  switch (type) {
    case ShapeType::Sphere:
      return "sphere";
    case ShapeType::Box:
      return "box";
    case ShapeType::Capsule:
      return "capsule";
    case ShapeType::Cylinder:
      return "cylinder";
    case ShapeType::Plane:
      return "plane";
    case ShapeType::Convex:
      return "convex";
    case ShapeType::Mesh:
      return "mesh";
    case ShapeType::Ellipsoid:
      return "ellipsoid";
  }
  return "unknown";
}

bool isStaticOnly(ShapeType type) {
  return type == ShapeType::Plane || type == ShapeType::Mesh;
}

}  // namespace linx
