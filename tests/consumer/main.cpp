// Built against the installed package, with the README's example code: a 1 m rod pendulum
// released horizontal must swing to the bottom in a quarter of its exact period,
// T/4 = 1.933335 s / 4 = 0.4833 s (shared reference: physical pendulum at 90 degrees).
#include <linx/linx.hpp>

#include <cmath>
#include <cstdio>

int main() {
  linx::World world;  // gravity (0, 0, -9.81), h = 1 ms, exact solver
  linx::BodyDef rod{.name = "rod", .mass = 1.0, .position = {0.5, 0, 0}};
  rod.inertia = linx::Vec3(1e-4, 1.0 / 12, 1.0 / 12).asDiagonal();
  const linx::BodyId id = world.createBody(rod);
  const linx::JointId pivot = world.createJoint(linx::HingeDef{
      .name = "pivot", .body1 = id, .anchor = linx::Vec3::Zero(), .axis = linx::Vec3::UnitY()});
  double t_bottom = -1.0;
  while (world.time() < 1.0 && t_bottom < 0.0) {
    world.step();
    if (world.jointCoordinates(pivot)[0] >= M_PI / 2) t_bottom = world.time();
  }
  std::printf("bottom reached at t = %.4f s (exact 0.4833 s)\n", t_bottom);
  return std::abs(t_bottom - 1.933335 / 4.0) < 2e-3 ? 0 : 1;
}
