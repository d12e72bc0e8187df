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
  }
  return "unknown";
}

}  // namespace linx
