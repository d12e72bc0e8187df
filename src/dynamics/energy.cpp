#include "dynamics/energy.hpp"

namespace linx::dynamics {

Energy computeEnergy(std::span<const Body> bodies, const Vec3& gravity) {
  Energy e;
  for (const Body& b : bodies) {
    if (b.isStatic()) continue;
    e.kinetic += b.kineticEnergy();
    e.potential -= b.mass() * gravity.dot(b.position());
  }
  return e;
}

}  // namespace linx::dynamics
