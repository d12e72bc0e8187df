// Geometric stiffness (Andrews, Erleben & Ferguson, "Geometric Stiffness for Real-time Constrained
// Multibody Dynamics", 2017). A joint's force turns as its bodies turn: a link under tension is
// held straight by it like a pendulum by gravity, a mode of angular frequency w^2 = K / I, with
// K = d(J^T f)/dq the joint's stiffness (Joint::stiffness) for its force f. The velocity solve
// holds the force's direction over the step, which is explicit in that mode: stable only while
// h w stays small, and a chain whose light links carry a heavy bob (w^2 = 1e4 N x 5 cm / 9e-4 kg
// m^2 at h = 1/240 s: h w = 3) gains energy until it flies apart. Adding h^2 K to the bodies'
// masses in the solve (and in the post-stabilization's metric) treats the mode implicitly, with the
// O(n) tree factorization kept: K is lumped onto each body's diagonal, the norms of its columns,
// and only the part beyond the body's own inertia is added, so that a body is stiffened only where
// h^2 K > I (h w > 1): a plain chain keeps its dynamics, the heavy chain is damped in the mode the
// step cannot follow. K is taken with the last step's impulses (the warm start).
#pragma once

#include <linx/body.hpp>
#include <linx/joint.hpp>
#include <linx/row.hpp>
#include <linx/solver.hpp>

#include "solver/problem.hpp"

#include <memory>
#include <span>
#include <vector>

namespace linx::state {
class Archive;
}

namespace linx::step {

class GeometricStiffness {
 public:
  /// Measures h^2 |K| per body (lumped: each column's norm on its coordinate) for the joints'
  /// `rows` of this step (in joint order, as assembled) and their impulses of the last step
  /// (`lambda`, the warm start).
  void measure(std::span<const std::unique_ptr<Joint>> joints, std::span<const Body> bodies,
               const SolverSettings& settings, double h, std::span<const Row> rows,
               std::span<const double> lambda);
  /// Forgets the last measure: no body is stiffened.
  void clear() { measured_.clear(); }
  /// What is added to body i's mass (3, the largest serves) and inertia about the world axes (3):
  /// the measured h^2 |K| beyond the body's own (at the measure's poses).
  Vec6 added(std::size_t i) const;
  /// The solver body of body i with added() added to its mass and inertia.
  void stiffen(std::size_t i, const Body& body, solver::SolverBody& b) const;
  /// The body's own share of its stiffened inertia about the row direction w (1 when nothing is
  /// added).
  double ownShare(std::size_t i, const Body& body, const Vec3& w) const;

  /// Reads or writes what carries to the next step (World::saveState).
  void persist(state::Archive& archive);

 private:
  std::vector<Vec6> measured_;  // per body: added(), world axes
};

}  // namespace linx::step
