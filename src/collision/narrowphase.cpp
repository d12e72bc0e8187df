// The narrowphase dispatcher: picks the routine for a pair of shape types. Exact routines serve
// the primitive pairs (collision/primitive_pairs.hpp); hulls, cylinders and ellipsoids against
// anything but a plane, and every pair with a triangle mesh go through the general convex routines
// (collision/convex_pairs.hpp). A routine is written for one order of its two types; the other
// order calls it swapped and turns the normals of the points it appended around.
#include "collision/narrowphase.hpp"

#include <utility>

#include "collision/convex_pairs.hpp"
#include "collision/primitive_pairs.hpp"

namespace linx::collision {

namespace {
using Routine = int (*)(const ShapeInstance&, const ShapeInstance&, double,
                        std::vector<ContactPoint>&);

int swapped(Routine routine, const ShapeInstance& a, const ShapeInstance& b, double margin,
            std::vector<ContactPoint>& out) {
  const std::size_t first = out.size();
  const int n = routine(b, a, margin, out);
  for (std::size_t k = first; k < out.size(); ++k) out[k].normal = -out[k].normal;
  return n;
}

/// The routine for types (ta, tb) in this order, or nullptr when only the other order has one.
Routine routineFor(ShapeType ta, ShapeType tb) {
  using T = ShapeType;
  if (tb == T::Mesh) return ta == T::Mesh || ta == T::Plane ? nullptr : &collideMesh;
  if (ta == T::Mesh) return nullptr;
  if (ta == T::Plane) {
    if (tb == T::Plane) return nullptr;
    return &collidePlane;
  }
  if (tb == T::Plane) return nullptr;
  if (ta == T::Convex || tb == T::Convex || ta == T::Cylinder || tb == T::Cylinder ||
      ta == T::Ellipsoid || tb == T::Ellipsoid)
    return &collideConvex;
  // Primitive pairs, in the order sphere < capsule < box.
  switch (ta) {
    case T::Sphere:
      return tb == T::Sphere    ? &collideSphereSphere
             : tb == T::Capsule ? &collideSphereCapsule
                                : &collideSphereBox;
    case T::Capsule:
      return tb == T::Capsule ? &collideCapsuleCapsule
             : tb == T::Box   ? &collideCapsuleBox
                              : nullptr;
    case T::Box:
      return tb == T::Box ? &collideBoxBox : nullptr;
    default:
      return nullptr;
  }
}
}  // namespace

int collide(const ShapeInstance& a, const ShapeInstance& b, double margin,
            std::vector<ContactPoint>& out) {
  const ShapeType ta = a.def->type, tb = b.def->type;
  if (isStaticOnly(ta) && isStaticOnly(tb)) return 0;
  if (Routine r = routineFor(ta, tb)) return r(a, b, margin, out);
  if (Routine r = routineFor(tb, ta)) return swapped(r, a, b, margin, out);
  return 0;
}

}  // namespace linx::collision
