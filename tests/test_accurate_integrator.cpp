// The accurate integrator (docs/integrators.md): energy and joint errors of mechanisms over long
// runs, against conservation of energy and the joints' own geometry.
#include "support.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

namespace linx {
namespace {

WorldSettings accurateSettings(double h) {
  WorldSettings s;
  s.timestep = h;
  s.integrator.type = IntegratorType::Accurate;
  return s;
}

double largestJointError(const World& w) {
  double e = 0.0;
  for (const JointId id : w.jointIds()) e = std::max(e, w.jointError(id));
  return e;
}

// A chain of `links` uniform rods (1 kg, 0.2 m, no shapes: nothing touches) hinged end to end
// about y, the first to the world at the origin, released horizontal along +x.
World horizontalChain(int links, const WorldSettings& s) {
  World w(s);
  BodyId previous;
  const double length = 0.2;
  for (int i = 0; i < links; ++i) {
    BodyDef d = test::boxBody("link" + std::to_string(i), 1.0, Vec3(length, 0.02, 0.02),
                              Vec3((i + 0.5) * length, 0, 0));
    d.shapes.clear();
    const BodyId id = w.createBody(d);
    JointDef j{.name = "hinge" + std::to_string(i),
               .body1 = i == 0 ? id : previous,
               .anchor = Vec3(i * length, 0, 0),
               .axis = Vec3::UnitY()};
    if (i > 0) j.body2 = id;
    w.createJoint("hinge", j);
    previous = id;
  }
  return w;
}

TEST(AccurateIntegrator, FiveLinkChainKeepsItsEnergy) {
  World w = horizontalChain(5, accurateSettings(1e-3));
  const double e0 = w.energy().total();
  double exchanged = 0.0, drift = 0.0, joint = 0.0;
  const auto start = std::chrono::steady_clock::now();
  while (w.time() < 10.0 - 1e-9) {
    w.step();
    exchanged = std::max(exchanged, w.energy().kinetic);
    drift = std::max(drift, std::abs(w.energy().total() - e0));
    joint = std::max(joint, largestJointError(w));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("exchanged %.6g J, drift %.3g J (%.3g), joints %.3g m, %.3f s\n", exchanged, drift,
              drift / exchanged, joint, seconds);
  EXPECT_LT(drift, 1e-6 * exchanged);
  EXPECT_LT(joint, 1e-8);
}

}  // namespace
}  // namespace linx
