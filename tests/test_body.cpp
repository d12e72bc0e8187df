// Single bodies: free flight against closed forms, loads, static bodies, and torque-free rotation
// (the gyroscopic term) against the conservation laws.
#include "dynamics/integrator.hpp"
#include "support.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace linx {
namespace {

TEST(Body, FreeFallMatchesTheSemiImplicitEulerClosedForm) {
  // Symplectic Euler under constant g: x_n = x0 + v0 t + g h^2 n(n+1)/2, exactly. The continuous
  // parabola differs from it by g h t / 2 only.
  WorldSettings s;
  s.gravity = Vec3(0.0, 0.0, -9.81);
  s.timestep = 1e-3;
  World w(s);
  BodyDef d = test::boxBody("b", 2.0, Vec3(0.1, 0.1, 0.1), Vec3(1, 2, 3));
  d.linear_velocity = Vec3(1.0, -0.5, 4.0);
  const BodyId id = w.createBody(d);
  const int n = 1000;
  for (int i = 0; i < n; ++i) w.step();
  const double h = s.timestep, t = n * h;
  const Vec3 discrete =
      d.position + d.linear_velocity * t + s.gravity * (h * h * n * (n + 1) / 2.0);
  EXPECT_LT((w.body(id).position() - discrete).norm(), 1e-12);
  const Vec3 parabola = d.position + d.linear_velocity * t + 0.5 * s.gravity * t * t;
  EXPECT_NEAR((w.body(id).position() - parabola).norm(), 0.5 * 9.81 * h * t, 1e-9);
}

TEST(Body, ForcesAndTorquesGiveNewtonEulerAccelerations) {
  WorldSettings s;
  s.gravity.setZero();
  s.timestep = 1e-2;
  World w(s);
  BodyDef d = test::boxBody("b", 4.0, Vec3(0.2, 0.4, 0.6), Vec3::Zero());
  const BodyId id = w.createBody(d);
  w.body(id).applyForce(Vec3(8.0, 0.0, 0.0));
  w.body(id).applyTorque(Vec3(0.0, 0.0, 0.5));
  w.step();
  EXPECT_NEAR(w.body(id).linearVelocity().x(), 8.0 / 4.0 * s.timestep, 1e-15);
  const double izz = (*d.inertia)(2, 2);
  EXPECT_NEAR(w.body(id).angularVelocity().z(), 0.5 / izz * s.timestep, 1e-14);
  // Loads last one step.
  w.step();
  EXPECT_NEAR(w.body(id).linearVelocity().x(), 8.0 / 4.0 * s.timestep, 1e-15);
}

TEST(Body, StaticBodiesNeverMove) {
  World w;
  BodyDef d = test::boxBody("ground", 1.0, Vec3(1, 1, 1), Vec3(0, 0, -1));
  d.is_static = true;
  d.linear_velocity = Vec3(1, 0, 0);
  const BodyId id = w.createBody(d);
  for (int i = 0; i < 100; ++i) w.step();
  EXPECT_EQ(w.body(id).position(), Vec3(0, 0, -1));
  EXPECT_EQ(w.body(id).linearVelocity(), Vec3::Zero());
  EXPECT_EQ(w.energy().total(), 0.0);
}

TEST(Body, RejectsBadDefinitions) {
  World w;
  BodyDef d = test::boxBody("b", 1.0, Vec3(1, 1, 1), Vec3::Zero());
  d.mass = 0.0;
  EXPECT_THROW(w.createBody(d), std::invalid_argument);
  d.mass = 1.0;
  d.inertia = Vec3(1.0, -1.0, 1.0).asDiagonal();
  EXPECT_THROW(w.createBody(d), std::invalid_argument);
  // Principal moments break the triangle inequality (100 > 1 + 1): no rigid body has them. A thin
  // plate's (1, 2, 3: the largest the sum of the others) is the limit, and accepted.
  d.inertia = Vec3(1.0, 1.0, 100.0).asDiagonal();
  try {
    w.createBody(d);
    ADD_FAILURE() << "accepted inertia [1, 1, 100]";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not a rigid body's"), std::string::npos) << e.what();
  }
  d.inertia = Vec3(1.0, 2.0, 3.0).asDiagonal();
  d.name = "plate";
  EXPECT_NO_THROW(w.createBody(d));
  d.name = "b";
  d.inertia = Mat3::Identity();
  d.position.x() = std::nan("");
  EXPECT_THROW(w.createBody(d), std::invalid_argument);
  d.position.x() = 0.0;
  w.createBody(d);
  EXPECT_THROW(w.createBody(d), std::invalid_argument);  // duplicate name
}

TEST(Body, MassAndInertiaComeFromTheShapesWhenLeftOut) {
  World w;
  // Densities only: a 0.1 m steel sphere, m = rho 4/3 pi r^3, I = 2/5 m r^2; and a 0.2 x 0.4 x 0.6
  // m box offset by 0.5 m along x beside it: the centre of mass moves to the common one.
  BodyDef d;
  d.name = "compound";
  d.position = Vec3(1, 2, 3);
  d.shapes = {ShapeDef{.type = ShapeType::Sphere, .radius = 0.1, .density = 7800.0},
              ShapeDef{.type = ShapeType::Box,
                       .size = Vec3(0.2, 0.4, 0.6),
                       .position = Vec3(0.5, 0, 0),
                       .density = 1000.0}};
  const Body& b = w.body(w.createBody(d));
  const double ms = 7800.0 * 4.0 / 3.0 * M_PI * 1e-3, mb = 1000.0 * 0.2 * 0.4 * 0.6;
  const double x = mb * 0.5 / (ms + mb);  // the common centre, from the sphere's
  EXPECT_NEAR(b.mass(), ms + mb, 1e-9);
  EXPECT_NEAR((b.position() - Vec3(1 + x, 2, 3)).norm(), 0.0, 1e-12);
  // Izz about the common centre: 2/5 ms r^2 + ms x^2 + mb (0.2^2 + 0.4^2) / 12 + mb (0.5 - x)^2.
  const double izz =
      0.4 * ms * 0.01 + ms * x * x + mb * (0.04 + 0.16) / 12.0 + mb * (0.5 - x) * (0.5 - x);
  EXPECT_NEAR(b.inertiaBody()(2, 2), izz, 1e-9);
  // A mass alone: the inertia of the shape filled to it (a 2 kg box: m (b^2 + c^2) / 12).
  BodyDef e = test::boxBody("box", 2.0, Vec3(0.2, 0.4, 0.6), Vec3::Zero());
  e.inertia.reset();
  EXPECT_NEAR(w.body(w.createBody(e)).inertiaBody()(0, 0), 2.0 * (0.16 + 0.36) / 12.0, 1e-12);
}

TEST(Body, MassPropertiesThatContradictOrAreMissingAreRefused) {
  World w;
  const auto message = [&](const BodyDef& d) {
    try {
      w.createBody(d);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  BodyDef d;
  d.name = "b";
  EXPECT_EQ(message(d), "shapes: no solid shape to compute the mass from");
  d.inertia = Mat3::Identity();
  EXPECT_EQ(message(d), "inertia: give the mass with the inertia, or neither");
  d.inertia.reset();
  d.mass = 1.0;
  EXPECT_EQ(message(d), "inertia: missing (give it, or a solid shape to compute it from)");
  d.mass = -2.0;  // checked before an inertia is made from it
  d.shapes = {ShapeDef{.type = ShapeType::Box, .size = Vec3::Ones()}};
  EXPECT_EQ(message(d), "mass: must be finite and > 0");
  d.shapes.clear();
  d.mass.reset();
  d.shapes = {ShapeDef{.type = ShapeType::Sphere, .radius = 0.1}};
  EXPECT_EQ(message(d), "shapes[0].density: a density >= 0 is needed to compute the mass");
  // A mass and a density that disagree: one of them would be ignored.
  d.shapes[0].density = 1000.0;
  d.mass = 1.0;
  EXPECT_EQ(message(d).substr(0, 40), "mass: 1 kg, but the shapes' densities ma");
  // ... and that agree: accepted.
  d.mass = 1000.0 * 4.0 / 3.0 * M_PI * 1e-3;
  EXPECT_EQ(message(d), "(accepted)");
  d.name = "";
  EXPECT_EQ(message(d), "name: must not be empty");
}

// Intermediate-axis (Dzhanibekov) spin: I = diag(1, 2, 3) kg m^2, spin 6 rad/s about the middle
// axis with a 0.1 rad/s perturbation: the body flips over and back every second or so. Without
// torque, kinetic energy and the world-frame angular momentum are constant.
struct Spin {
  double energy_drift, momentum_drift, momentum_direction_drift;
  int flips;
};

Spin spinIntermediateAxis(double h, double seconds) {
  WorldSettings s;
  s.gravity.setZero();
  s.timestep = h;
  World w(s);
  BodyDef d;
  d.name = "t-handle";
  d.mass = 1.0;
  d.inertia = Vec3(1.0, 2.0, 3.0).asDiagonal();
  d.angular_velocity = Vec3(0.1, 6.0, 0.0);
  const BodyId id = w.createBody(d);
  const double e0 = w.body(id).kineticEnergy();
  const Vec3 l0 = w.body(id).angularMomentum();
  Spin out{0, 0, 0, 0};
  double last_sign = 1.0;
  const int n = static_cast<int>(std::lround(seconds / h));
  for (int i = 0; i < n; ++i) {
    w.step();
    const Body& b = w.body(id);
    out.energy_drift = std::max(out.energy_drift, std::abs(b.kineticEnergy() - e0) / e0);
    const Vec3 l = b.angularMomentum();
    out.momentum_drift = std::max(out.momentum_drift, std::abs(l.norm() - l0.norm()) / l0.norm());
    out.momentum_direction_drift =
        std::max(out.momentum_direction_drift, (l - l0).norm() / l0.norm());
    // Body y axis against the (fixed) momentum direction: its sign changes at every flip.
    const double sign = (b.orientation() * Vec3::UnitY()).dot(l0) >= 0.0 ? 1.0 : -1.0;
    if (sign != last_sign) ++out.flips;
    last_sign = sign;
  }
  return out;
}

TEST(Body, TorqueFreeIntermediateAxisSpinConservesEnergyAndMomentum) {
  const Spin s = spinIntermediateAxis(1e-3, 30.0);
  RecordProperty("flips", s.flips);
  std::printf("flips %d, energy drift %.3e, |L| drift %.3e, L drift %.3e\n", s.flips,
              s.energy_drift, s.momentum_drift, s.momentum_direction_drift);
  EXPECT_GE(s.flips, 8);  // many flips over 30 s
  // The implicit midpoint gyroscopic step keeps 1/2 w.I w and |I w| exactly; what remains is the
  // orientation update's O(h^2) per step and round-off.
  EXPECT_LT(s.energy_drift, 1e-9);
  EXPECT_LT(s.momentum_drift, 1e-9);
  EXPECT_LT(s.momentum_direction_drift, 1e-2);
}

TEST(Body, FastAsymmetricSpinStaysStableAtLargeSteps) {
  // h |w| = 1 rad per step: an explicit gyroscopic term would blow up here.
  const Spin s = spinIntermediateAxis(1.0 / 6.0, 200.0);
  EXPECT_LT(s.energy_drift, 1e-6);
  EXPECT_LT(s.momentum_drift, 1e-6);
}

TEST(Body, GyroscopicStepIsTheImplicitMidpointRule) {
  const Mat3 inertia = Vec3(1.0, 2.0, 3.0).asDiagonal();
  const Vec3 w0(0.3, 5.0, -1.0);
  const double h = 0.01;
  const Vec3 w1 = dynamics::gyroscopicStep(inertia, w0, h);
  const Vec3 wm = 0.5 * (w0 + w1);
  const Vec3 residual = inertia * (w1 - w0) + h * wm.cross(inertia * wm);
  EXPECT_LT(residual.norm(), 1e-13);
}

}  // namespace
}  // namespace linx

namespace linx {
namespace {

TEST(Body, SubstepsSplitTheStepAndTheClockStaysExact) {
  // With k substeps a step of h is k steps of h/k: x_n = x0 + g (h/k)^2 N (N + 1) / 2, N = n k.
  WorldSettings s;
  s.timestep = 1e-2;
  s.solver.substeps = 4;
  World w(s);
  const BodyId id = w.createBody(test::boxBody("b", 1.0, Vec3(0.1, 0.1, 0.1), Vec3::Zero()));
  for (int i = 0; i < 100; ++i) w.step();
  const double hs = s.timestep / 4, big_n = 400;
  EXPECT_NEAR(w.body(id).position().z(), -9.81 * hs * hs * big_n * (big_n + 1) / 2, 1e-12);
  EXPECT_EQ(w.time(), 1.0);  // 100 steps of 0.01 s, with no accumulated round-off
  EXPECT_EQ(w.stepCount(), 100);
}

}  // namespace
}  // namespace linx
