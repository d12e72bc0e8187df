// The accurate integrator (issue 19, docs/integrators.md): islands whose constraints are joints
// alone move by the Dormand-Prince 5(4) Runge-Kutta pair on the index-1 equations of motion
// (step/constrained_dynamics), each of its steps projected back onto the joints' manifold
// (step/manifold_projection), the step size chosen by the local error estimate so that a frame of
// the world's step is split where the motion needs it. Fifth order: a pendulum chain keeps its
// energy to 1e-9 where the velocity-level step loses most of it.
//
// The state of a body is its position, its orientation quaternion taken as four numbers
// (dq/dt = 1/2 (0, w) q, normalized where the joints read it and after each step) and its linear
// and angular velocity in the world frame.
#pragma once

#include <linx/body.hpp>
#include <linx/joint.hpp>
#include <linx/row.hpp>
#include <linx/world.hpp>

#include "step/constrained_dynamics.hpp"
#include "step/islands.hpp"
#include "step/manifold_projection.hpp"
#include "step/row_events.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace linx::state {
class Archive;
}

namespace linx::step {

/// What the bodies bring to the accurate integrator from elsewhere: the step, the user, their
/// initial state.
///
/// The step updates a velocity before the positions move by it (symplectic Euler): its velocity
/// is, to second order, the one half a (sub)step earlier. A body that comes from the step to the
/// accurate integrator catches up by that much of its acceleration (`behind`, `time`), and one that
/// goes from it to the step falls back by it (velocityLag): without it an oscillator jumps in
/// amplitude by up to omega h at each switch.
///
/// A state the accurate integrator did not leave (`unprojected`) may be off the joints: the step
/// holds them to its solver's tolerance and error reduction, a pose or a velocity given between
/// steps or at creation not at all. Its index-1 equations keep a velocity's violation J u for the
/// whole step, and the projection after it would take the position's away only then, so such a
/// state is projected onto the manifold first (consistent initial values).
struct Handover {
  std::span<const std::uint8_t> behind;  ///< one flag per body: its velocity is the step's
  double time = 0.0;                     ///< (s) half the step's (sub)step
  /// One flag per body: its state is not one the accurate integrator left. Empty: no body's is.
  std::span<const std::uint8_t> unprojected;
};

/// Whether one of row r's bodies is flagged in `flags` (one per body).
bool onFlaggedBody(const Row& r, std::span<const std::uint8_t> flags);

class AccurateIntegrator {
 public:
  /// Flags in `accurate` (one per body) the bodies of the awake islands it moves: islands of
  /// dynamic bodies whose rows are all joint equalities it holds (holdsExactly), rows it switches
  /// (mayHold: limits, velocity motors and joint friction, events of its steps, step/row_events)
  /// or rows it applies as forces (actsAsForce: coordinate forces, springs, servos); an island
  /// with a contact, armature, a prescribed motion or a joint to a kinematic body takes the step.
  /// With `trying` (integrator "auto"), so does an island without a joint row (a free body: the
  /// step keeps its energy already) and one with a velocity row (a velocity motor, joint
  /// friction: driven or dissipative motion, which one accurate step a frame buys little of, at 2
  /// to 3 times the step's cost: a motor-driven slider-crank 2.9 times, measured). The first
  /// `joint_rows` rows are the joints'. Returns how many bodies it flagged.
  int select(std::span<const std::unique_ptr<Joint>> joints, std::span<const Body> bodies,
             std::span<const Row> rows, std::size_t joint_rows, const Islands& islands,
             std::span<const std::uint8_t> island_awake, const SolverSettings& settings,
             bool trying, std::vector<std::uint8_t>& accurate);

  /// Moves the flagged bodies from their state at `time` to time + h. Writes each of `rows`' share
  /// of the joints' impulses over the frame into `lambda`, and its mean direction over the frame
  /// into its J (by key; the rows of the flagged bodies), so that J^T lambda is what the joint
  /// applied over the frame (body1's torque: the mean about the moving anchor, taken about
  /// body1's centre at the frame's end, where the joint's loads are measured).
  /// Throws std::domain_error when the state stops being finite or the step size collapses.
  IntegratorReport advance(std::span<const std::unique_ptr<Joint>> joints, std::span<Body> bodies,
                           const WorldSettings& settings, std::span<const std::uint8_t> accurate,
                           const Handover& lag, double time, double h, int threads,
                           std::span<Row> rows, std::span<double> lambda);

  /// Integrator "auto": one step of length h for each flagged island, from the bodies' state at
  /// `time`. An island whose local error stays within its share of the tolerance (`limits`, per
  /// island) and whose step meets no switched row's event (but at its start) keeps it (projected,
  /// its impulses into `rows` and `lambda` as with advance); the flags of the others are cleared in
  /// `accurate`, their bodies left for the caller to put back. `islands`: those of the bodies.
  IntegratorReport tryOneStep(std::span<const std::unique_ptr<Joint>> joints,
                              std::span<Body> bodies, const WorldSettings& settings,
                              const Islands& islands, std::span<const double> limits,
                              std::vector<std::uint8_t>& accurate, const Handover& lag, double time,
                              double h, int threads, std::span<Row> rows, std::span<double> lambda);
  /// After tryOneStep, for a body it gave back to the step whose velocity was not behind: the lag
  /// the step's velocity should have, lag.time times its acceleration (linear, angular).
  std::pair<Vec3, Vec3> velocityLag(std::size_t body) const { return {lag_v_[body], lag_w_[body]}; }

  /// Reads or writes what carries to the next frame (World::saveState): the step size the last
  /// frame's error proposed.
  void persist(state::Archive& archive);

 private:
  /// One body's state, or its rate.
  struct Motion {
    Vec3 x = Vec3::Zero();
    Eigen::Vector4d q = Eigen::Vector4d::Zero();  // w, x, y, z
    Vec3 v = Vec3::Zero();
    Vec3 w = Vec3::Zero();
  };
  /// The rates of the bodies at `state` (written into the bodies first) and `time`, into `rate`;
  /// the joints' rows there, each with its force in place of its speed, into `forces`.
  void rates(std::span<const Motion> state, double time, std::span<Motion> rate,
             std::vector<Row>& forces);
  void put(std::span<const Motion> state, std::span<Body> bodies) const;
  /// From body1's centre of mass to the anchor of the joint that owns row `r` (keys
  /// (joint + 1) << 8 | slot), in the world frame, at the bodies' poses now.
  Vec3 anchorArm(const Row& r) const;
  /// Lends the frame's world to the steps below and sizes the buffers.
  void begin(std::span<const std::unique_ptr<Joint>> joints, std::span<Body> bodies,
             const WorldSettings& settings, std::span<const std::uint8_t> accurate, int threads);
  /// Whether one of the moving bodies is flagged in `flags` (one per body; empty: none).
  bool flaggedAny(std::span<const std::uint8_t> flags) const;
  /// y0 from the bodies; throws std::domain_error when it is not finite.
  void take();
  /// A frame's first step start, at `time`: the held rows on bodies `lag` says come from elsewhere
  /// are let go (RowEvents::keep); y0 from the bodies, its rates, the switched rows settled there
  /// (settleEvents); a state the accurate integrator did not leave projected onto the manifold
  /// with the rows held that hold at it (a motor the step kept at its target, a body resting on a
  /// limit), and settled again; then the bodies `lag` says are behind catch up,
  /// v += lag.time dv/dt, and the rates and rows are taken again.
  void startFrame(const Handover& lag, double time);
  /// One Runge-Kutta step of length dt from y0 (k_[0] holding its rates) at `time`: the stages,
  /// the fifth-order solution in y1, and the local error's norm against the tolerance. The
  /// switched rows' values at y1 (the last stage's state) into end_values_.
  double attempt(double time, double dt);
  /// At a step's start, y0 and k_[0] its rates at `time`: the rows whose events are there switch
  /// (RowEvents::settle), the state is projected with those held (a plastic impact for a limit
  /// that was closing, a locked row's rate onto its target) and its rates taken again, until none
  /// switches. The rows' values at y0 into start_values_, the bodies of the rows that switched
  /// into switched_.
  void settleEvents(double time);
  /// The switched rows' values at the state of the last rates().
  void measureEvents(std::vector<EventValue>& out) const {
    events_.measure(dynamics_.openRows(), dynamics_.rows(), dynamics_.forces(), bodies_, out);
  }
  /// Adds an accepted step's share of the joints' impulses (and their weighted directions).
  void addImpulses(double dt) { addImpulses(dt, {}); }
  /// The frame's impulses onto the rows (by key): lambda and each row's mean direction.
  void putImpulses(std::span<Row> rows, std::span<double> lambda) const;
  /// The largest component of `error` over its scale tol max(1, |y0|, |y1|): of all the moving
  /// bodies, or of the n-th.
  double errorNorm(double tolerance) const;
  double bodyError(std::size_t n, double tolerance) const;
  /// Names body `body` (a world index) with the bodies moved here and the joints that link it to
  /// them, for messages: "bodies[2] (bob), bodies[1] (arm) and joints 'pivot', 'elbow'".
  std::string namedIsland(int body) const;
  /// Adds a step's impulses; with `only`, those of the rows on a body it flags.
  void addImpulses(double dt, std::span<const std::uint8_t> only);

  std::span<const std::unique_ptr<Joint>> joints_;
  std::span<Body> bodies_;
  const WorldSettings* settings_ = nullptr;
  std::span<const std::uint8_t> moving_;
  int threads_ = 1;
  double next_step_ = 0.0;  // (s) the size the last step's error proposed; 0: none yet

  std::vector<int> ids_;  // the moving bodies
  std::vector<Motion> y0_, y_, y1_, error_;
  std::array<std::vector<Motion>, 7> k_;
  /// A row's impulse over the frame and its Jacobian weighted by it: the sum over the stages of
  /// w dt F J, whose division by the impulse gives the row's mean direction over the frame.
  struct Impulse {
    double lambda = 0.0;
    Vec6 Ja = Vec6::Zero(), Jb = Vec6::Zero(), Jc = Vec6::Zero(), Jd = Vec6::Zero();
  };
  std::array<std::vector<Row>, 7> stage_rows_;  // each stage's rows, with their force in `speed`
  std::unordered_map<std::uint64_t, Impulse> impulses_;
  std::vector<Vec3> dv_, dw_;
  std::vector<Vec3> lag_v_, lag_w_;  // tryOneStep: velocityLag, one per body
  std::vector<std::uint8_t> island_ok_;
  std::vector<double> island_error_;
  ConstrainedDynamics dynamics_;
  ManifoldProjection projection_;
  RowEvents events_;
  std::vector<EventValue> start_values_, end_values_;
  std::vector<std::uint64_t> released_;
  std::vector<int> switched_;
};

}  // namespace linx::step
