#include "step/step.hpp"

#include "dynamics/integrator.hpp"
#include "parallel/parallel_for.hpp"
#include "solver/soft_solver.hpp"
#include "step/assembly.hpp"
#include "step/substep_joints.hpp"

#include <algorithm>
#include <numbers>

namespace linx::step {

namespace {

/// Bodies from which the per-body stages of a pass are split over the threads.
constexpr std::ptrdiff_t kParallelBodies = 4096;

/// Runs body(i) for every body, split over the threads in large worlds (each writes only body i).
template <typename F>
void eachBody(const Scene& scene, F&& body) {
  parallel::forEach(static_cast<std::ptrdiff_t>(scene.bodies.size()), scene.threads,
                    kParallelBodies, [&](std::ptrdiff_t i) { body(static_cast<std::size_t>(i)); });
}

bool awake(const State& state, std::size_t body) {
  return !state.sleep.asleep(static_cast<int>(body));
}

// --- the stages, in the order pass() runs them ---------------------------------------------------

/// wake: a sleeping body that was given a velocity or a load since the last pass wakes, with the
/// bodies it touched (its island follows at the islands stage); a moving kinematic body wakes the
/// bodies it touched.
void wakeDisturbed(const Scene& scene, State& state) {
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const Body& b = scene.bodies[i];
    if ((!awake(state, i) && (b.isMoving() || !b.force().isZero(0) || !b.torque().isZero(0))) ||
        (b.isKinematic() && b.isMoving()))
      wakeWithNeighbours(scene.bodies, state, static_cast<int>(i));
  }
}

/// velocities: u* for every awake body (sleeping bodies stay at rest).
void integrateVelocities(const Scene& scene, const State& state, double h) {
  eachBody(scene, [&](std::size_t i) {
    if (awake(state, i)) dynamics::integrateVelocity(scene.bodies[i], scene.settings.gravity, h);
  });
}

/// collide: this pass's contact points from the bodies' poses and velocities.
void collide(const Scene& scene, State& state, double h, const ContactSettings& settings) {
  state.contact.detect(scene.bodies, scene.joints, settings, h, scene.threads);
}

/// prepare: the joints' rows, then three rows per contact point, each with its warm start.
/// `h_joints` is the length the joints' rows act over (a motor's bound is h F), `h` the step's;
/// `bounce`: restitution as the normal rows' target (the soft step applies it after its substeps);
/// `curvature`: with post-stabilization on, the joints' rows aim at their manifold to second order
/// (step/stabilization; the soft step's joints do so in each substep).
void prepareRows(const Scene& scene, State& state, double h_joints, double h, bool bounce,
                 bool curvature) {
  const SolverSettings& solver = scene.settings.solver;
  Rows& r = state.rows;
  assembleRows(scene.joints, scene.bodies, solver, h_joints, scene.time, r.rows,
               state.start_velocities);
  r.joint_rows = r.rows.size();
  r.lambda.assign(r.joint_rows, 0.0);
  if (solver.warm_start) state.joint_warm.load(r.rows, r.lambda);
  if (solver.geometric_stiffness) {
    // The last impulses, whether or not they start the solve.
    std::vector<double>& last = state.last_joint_impulses;
    if (!solver.warm_start) {
      last.assign(r.joint_rows, 0.0);
      state.joint_warm.load(r.rows, last);
    }
    state.geometric_stiffness.measure(scene.joints, scene.bodies, solver, h_joints, r.rows,
                                      solver.warm_start ? r.lambda : last);
  } else {
    state.geometric_stiffness.clear();
  }
  if (curvature && solver.post_stabilization > 0) {
    state.stabilization.beginStep(scene.bodies);
    state.stabilization.addCurvature(scene.bodies, r.rows, true, &state.geometric_stiffness);
  }
  state.contact.appendRows(scene.bodies, h, r.rows, r.lambda, solver.warm_start, scene.threads,
                           bounce, state.start_velocities);
}

/// islands: bodies linked by this pass's rows. With sleeping on, an island with an awake body
/// wakes entirely, and the bodies it wakes get this pass's velocity update (`h` > 0; the soft
/// step integrates velocities in its substeps); with it off, every body is awake. Returns one
/// awake flag per island (empty: all awake).
std::span<const std::uint8_t> buildIslands(const Scene& scene, State& state, double h) {
  rowLinks(state.rows.rows, state.links);
  const std::size_t n = scene.bodies.size();
  state.movable.resize(n);
  for (std::size_t i = 0; i < n; ++i) state.movable[i] = scene.bodies[i].isDynamic();
  state.islands.build(static_cast<int>(n), state.movable, state.links);
  if (!scene.settings.sleep.enabled) {
    for (std::size_t i = 0; i < n; ++i)
      if (!awake(state, i)) dynamics::integrateVelocity(scene.bodies[i], scene.settings.gravity, h);
    state.sleep.wakeAll();
    return {};
  }
  std::vector<std::uint8_t>& was_asleep = state.may_sleep;  // scratch until the sleep stage
  was_asleep.resize(n);
  for (std::size_t i = 0; i < n; ++i) was_asleep[i] = !awake(state, i);
  const std::span<const std::uint8_t> island_awake = state.sleep.wakeIslands(state.islands);
  for (std::size_t i = 0; i < n && h > 0.0; ++i)
    if (was_asleep[i] && awake(state, i))
      dynamics::integrateVelocity(scene.bodies[i], scene.settings.gravity, h);
  return island_awake;
}

/// A pose or velocity set between steps (World, the user's code) is the body's at the time of its
/// position: it is not behind, whatever moved the body before, and may be off the joints. A body
/// whose state the accurate integrator did not leave (behind, or without a pass yet) may be too.
void noteSetStates(const Scene& scene, State& state) {
  const std::size_t n = scene.bodies.size();
  // Before the first pass, or with bodies added since, every state is new (and none is behind).
  const bool known = state.behind.size() == n;
  state.behind.resize(n, 0);
  state.unprojected.assign(n, known ? 0 : 1);
  if (!known) return;
  const bool compare = state.left.size() == n;
  for (std::size_t i = 0; i < n; ++i) {
    const Body& b = scene.bodies[i];
    if (compare) {
      const BodyState& left = state.left[i];
      if (b.linearVelocity() != left.v || b.angularVelocity() != left.w ||
          b.position() != left.pose.position ||
          b.orientation().coeffs() != left.pose.orientation.coeffs()) {
        state.behind[i] = 0;
        state.unprojected[i] = 1;
      }
    }
    if (state.behind[i]) state.unprojected[i] = 1;
  }
}

/// Keeps each body's state as the pass leaves it (noteSetStates).
void keepLeftStates(const Scene& scene, State& state) {
  state.left.resize(scene.bodies.size());
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const Body& b = scene.bodies[i];
    state.left[i] = BodyState{b.pose(), b.linearVelocity(), b.angularVelocity()};
  }
}

/// After the accurate stage: the awake bodies the step moves this pass are behind (Handover),
/// those the accurate integrator moves are not.
void markBehind(const Scene& scene, State& state, std::span<const std::uint8_t> island_awake) {
  state.behind.resize(scene.bodies.size(), 0);
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const int island = state.islands.islandOf(static_cast<int>(i));
    const bool sleeping =
        !island_awake.empty() && island >= 0 && !island_awake[static_cast<std::size_t>(island)];
    if (scene.bodies[i].isDynamic() && !sleeping) state.behind[i] = !state.accurate_bodies[i];
  }
}

/// "auto": the flagged islands try one step of the accurate integrator (from the start velocities
/// the bodies hold, their state before in `before_accurate`); those that refuse are cleared from
/// `accurate_bodies` and take the solve from where the velocities stage left them, behind by the
/// step's lag if the accurate integrator had moved them.
void tryOneAccurateStep(const Scene& scene, State& state, const Handover& lag, double h) {
  std::vector<std::uint8_t>& accurate = state.accurate_bodies;
  std::vector<std::uint8_t>& tried = state.tried_accurate;
  tried = accurate;
  state.accurate_report = state.accurate.tryOneStep(
      scene.joints, scene.bodies, scene.settings, state.islands, state.choice.errorLimits(),
      accurate, lag, scene.time, h, scene.threads, state.rows.rows, state.rows.lambda);
  state.choice.record(tried, accurate);
  std::size_t k = 0;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    if (!tried[i]) continue;
    const BodyState& b = state.before_accurate[k++];
    if (accurate[i]) continue;
    const auto [lag_v, lag_w] = state.accurate.velocityLag(i);
    scene.bodies[i].setPose(b.pose);
    scene.bodies[i].setLinearVelocity(b.v - lag_v);
    scene.bodies[i].setAngularVelocity(b.w - lag_w);
  }
}

/// accurate: with integrator "accurate", the awake islands of joints alone (no contact, velocity
/// motor, friction or armature rows; limits are events of its steps) move over the pass by the
/// accurate integrator from their state at its start (the velocities before the velocities stage),
/// and their joints' impulses become the rows'. With "auto", those of them not waiting
/// (step/integrator_choice) try one step of it and keep it where it holds the tolerance; the others
/// are put back for the solve. Returns the awake islands left to the solve (empty: all).
std::span<const std::uint8_t> integrateAccurately(const Scene& scene, State& state,
                                                  std::span<const std::uint8_t> island_awake,
                                                  double h, double lag) {
  state.accurate_report = IntegratorReport{};
  std::vector<std::uint8_t>& accurate = state.accurate_bodies;
  const IntegratorType type = scene.settings.integrator.type;
  int count =
      type == IntegratorType::Step
          ? 0
          : state.accurate.select(scene.joints, scene.bodies, state.rows.rows,
                                  state.rows.joint_rows, state.islands, island_awake,
                                  scene.settings.solver, type == IntegratorType::Auto, accurate);
  // (Every pass counts down the waits, whether or not an island could try.)
  if (type == IntegratorType::Auto) count = state.choice.keepTrying(state.islands, accurate);
  if (count == 0) {
    accurate.assign(scene.bodies.size(), 0);
    markBehind(scene, state, island_awake);
    return island_awake;
  }
  const Handover handover{state.behind, lag, state.unprojected};
  std::vector<BodyState>& before = state.before_accurate;
  before.clear();
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    if (!accurate[i]) continue;
    Body& b = scene.bodies[i];
    before.push_back(BodyState{b.pose(), b.linearVelocity(), b.angularVelocity()});
    b.setLinearVelocity(state.start_velocities[i].v);
    b.setAngularVelocity(state.start_velocities[i].w);
  }
  if (type == IntegratorType::Auto) {
    tryOneAccurateStep(scene, state, handover, h);
  } else {
    state.accurate_report =
        state.accurate.advance(scene.joints, scene.bodies, scene.settings, accurate, handover,
                               scene.time, h, scene.threads, state.rows.rows, state.rows.lambda);
  }
  markBehind(scene, state, island_awake);
  std::vector<std::uint8_t>& stepped = state.island_stepped;
  stepped.assign(static_cast<std::size_t>(state.islands.count()), 1);
  if (!island_awake.empty()) std::copy(island_awake.begin(), island_awake.end(), stepped.begin());
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
    if (accurate[i])
      stepped[static_cast<std::size_t>(state.islands.islandOf(static_cast<int>(i)))] = 0;
  return stepped;
}

bool accurate(const State& state, std::size_t body) {
  return body < state.accurate_bodies.size() && state.accurate_bodies[body] != 0;
}

/// The joint rows of the islands the accurate integrator moved, with their impulses over the pass
/// (the soft step measures its joints' loads in its substeps, without these).
void keepAccurateJointRows(const State& state, std::vector<Row>& rows,
                           std::vector<double>& lambda) {
  rows.clear();
  lambda.clear();
  if (state.accurate_report.bodies == 0) return;
  for (std::size_t k = 0; k < state.rows.joint_rows; ++k) {
    if (!onFlaggedBody(state.rows.rows[k], state.accurate_bodies)) continue;
    rows.push_back(state.rows.rows[k]);
    lambda.push_back(state.rows.lambda[k]);
  }
}

/// solve: gathers the compact solver bodies (u*), solves every awake island with the world's
/// solver; the solver bodies then hold u+ and the rows' impulses lambda. Sleeping islands keep
/// the impulses they rest on, for when they wake.
void gatherSolverBodies(const Scene& scene, State& state) {
  state.solver_bodies.resize(scene.bodies.size());
  eachBody(scene, [&](std::size_t i) {
    const Body& b = scene.bodies[i];
    state.solver_bodies[i] = solver::SolverBody{b.inverseMass(), b.inverseInertiaWorld(),
                                                b.linearVelocity(), b.angularVelocity()};
  });
}

/// The island of a row's movable end, -1 for none.
int islandOfRow(const State& state, const Row& r) {
  int island = -1;
  r.forEachBlock([&](int body, const Vec6&) {
    if (island < 0 && body >= 0) island = state.islands.islandOf(body);
  });
  return island;
}

SolverReport solve(const Scene& scene, State& state, std::span<const std::uint8_t> island_awake,
                   double h) {
  gatherSolverBodies(scene, state);
  const SolverSettings& settings = scene.settings.solver;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
    state.geometric_stiffness.stiffen(i, scene.bodies[i], state.solver_bodies[i]);
  if (!state.solver || state.solver_type != settings.type) {
    state.solver = solver::makeSolver(settings.type);
    state.solver_type = settings.type;
  }
  return solveIslands(state.islands, island_awake, state.rows.rows, state.solver_bodies,
                      state.rows.lambda, h, *state.solver, settings, state.island_work,
                      scene.threads);
}

/// substeps (the soft step's solve, positions and relax): the contact rows prepared once; per
/// substep of h = dt / n, velocities integrated, the joints' rows assembled at the current poses
/// (step/substep_joints), the impulses warm-started, one sweep over the contacts with the soft
/// bias and the joints solved exactly, positions integrated, one relax sweep without the bias
/// and the joints solved exactly again (solver/soft_solver.hpp); then restitution.
/// Rows of sleeping
/// islands keep their impulses and their bodies stay; the rows' impulses are the last
/// substep's, `state.soft_total` theirs over the step.
SolverReport substeps(const Scene& scene, State& state, std::span<const std::uint8_t> island_awake,
                      double dt) {
  const SolverSettings& settings = scene.settings.solver;
  const int n = std::max(1, settings.substeps);
  const double h = dt / n;
  const std::vector<Row>& rows = state.rows.rows;
  // A row acts when its island is awake (its movable end's island).
  state.island_work.row_island.resize(rows.size());
  std::vector<std::uint8_t>& active = state.row_active;
  active.resize(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const int island = islandOfRow(state, rows[k]);
    state.island_work.row_island[k] = island;
    active[k] = island >= 0 &&
                (island_awake.empty() || island_awake[static_cast<std::size_t>(island)] != 0);
    if (k < state.rows.joint_rows) active[k] = 0;  // the joints are solved exactly, below
  }
  // Manifolds: a contact's normal rows by shape pair (records come in pair order).
  std::vector<int>& manifold = state.row_manifold;
  manifold.assign(rows.size(), -1);
  {
    int id = -1;
    std::uint64_t pair = 0;
    for (const ContactRecord& r : state.contact.records()) {
      if (r.row < 0) continue;
      if (id < 0 || r.pair != pair) {
        ++id;
        pair = r.pair;
      }
      manifold[static_cast<std::size_t>(r.row)] = id;
    }
  }
  gatherSolverBodies(scene, state);
  const ContactSettings& contacts = scene.settings.contact;
  // A quarter of the substep rate is the stiffest one row can be and stay stable. A face's four
  // contact points act together, as one spring twice as fast: a stack of five boxes jittered at
  // a quarter (60 Hz with substeps of 1/240 s) and stands at an eighth, which contact hertz 0
  // (the default) takes; a given hertz is capped there.
  const double eighth = 0.125 / h;
  const double contact_hertz = contacts.hertz > 0.0 ? std::min(contacts.hertz, eighth) : eighth;
  solver::SoftSolver::Settings soft;
  soft.contact = solver::Softness::of(contact_hertz, contacts.damping_ratio, h);
  soft.max_push_out = contacts.max_push_out;
  soft.h = h;
  soft.substeps = n;
  soft.threads = scene.threads;
  // The spring holds a resting contact at its load over m omega^2 (g / omega^2 for a body on the
  // ground): each row keeps twice its load's depth in the velocities, whose sweeps the spring
  // damps, and at least twice a body's own; deeper, the push removes the penetration without
  // velocity (a box 1 mm deep at h = 1e-5 s, a 50 kHz spring, left at 1.1 m/s when all of it was
  // in the velocities; a fixed depth of 16 g / omega^2 let a column of 30 boxes fall).
  const double omega = 2.0 * std::numbers::pi * contact_hertz;
  soft.omega = omega;
  soft.spring_depth = 2.0 * scene.settings.gravity.norm() / (omega * omega);
  solver::SoftSolver& solver = state.soft;
  solver.prepare(rows, state.rows.lambda, active, manifold, state.solver_bodies, soft);
  const std::span<solver::SoftSolver::Body> bodies = solver.bodies();
  state.moving.resize(scene.bodies.size());
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
    state.moving[i] = scene.bodies[i].isDynamic() && awake(state, i) && !accurate(state, i);
  const auto moving = [&](std::size_t i) { return state.moving[i] != 0; };
  SubstepJoints& joints = state.substep_joints;
  SolverReport joint_report;
  const auto toBodies = [&] {
    eachBody(scene, [&](std::size_t i) {
      if (!moving(i)) return;
      scene.bodies[i].setLinearVelocity(bodies[i].v);
      scene.bodies[i].setAngularVelocity(bodies[i].w);
    });
  };
  for (int s = 0; s < n; ++s) {
    keepStartVelocities(scene.bodies, state.start_velocities);
    eachBody(scene, [&](std::size_t i) {
      if (!moving(i)) return;
      dynamics::integrateVelocity(scene.bodies[i], scene.settings.gravity, h);
      bodies[i].v = scene.bodies[i].linearVelocity();
      bodies[i].w = scene.bodies[i].angularVelocity();
    });
    const double start = scene.time + s * h;  // of this substep: the targets' time
    joints.prepare(scene.joints, scene.bodies, settings, h, start, state.moving, state.joint_warm,
                   state.stabilization, true, state.start_velocities);
    solver.warmStart();
    joints.warmStart(bodies);
    solver.solve();
    solver.push();
    if (!joints.empty()) joints.solve(bodies, true, settings, h, scene.threads);
    // The positions move by the velocities and the contacts' push velocities; the velocities
    // keep none of the push (the split impulse, solver/soft_solver.hpp). The last substep's push
    // keeps its islands awake (sleep), unless it would move a body less than a hundredth of the
    // slop (or 1e-5 rad) in the time it takes to fall asleep: the soft step's contacts have no
    // slop, and push for ever at a vanishing speed.
    if (s + 1 == n) state.island_work.push.assign(scene.bodies.size(), PushVelocity{});
    const double still = 1e-2 * scene.settings.contact.slop / scene.settings.sleep.time;
    const double still_w = 1e-5 / scene.settings.sleep.time;
    eachBody(scene, [&](std::size_t i) {
      if (moving(i)) {
        if (s + 1 == n && (bodies[i].push_v.norm() > still || bodies[i].push_w.norm() > still_w))
          state.island_work.push[i] = PushVelocity{bodies[i].push_v, bodies[i].push_w};
        scene.bodies[i].setLinearVelocity(bodies[i].v + bodies[i].push_v);
        scene.bodies[i].setAngularVelocity(bodies[i].w + bodies[i].push_w);
      }
      if (moving(i) || scene.bodies[i].isKinematic())
        dynamics::integratePosition(scene.bodies[i], h);
    });
    toBodies();
    solver.move(h);
    solver.relax();
    joints.store(state.joint_warm);
    joints.prepare(scene.joints, scene.bodies, settings, h, start, state.moving, state.joint_warm,
                   state.stabilization, false, state.start_velocities);
    if (!joints.empty()) joint_report = joints.solve(bodies, false, settings, h, scene.threads);
    solver.accumulate();
    joints.store(state.joint_warm);
    state.joint_loads.measure(joints.rows(), joints.impulses(), n * h, scene.joints, scene.bodies,
                              s > 0);
    toBodies();
  }
  // restitution: contacts that approached faster than the threshold at the start of the step
  // and took an impulse leave at e times that speed.
  state.bounces.clear();
  for (const ContactRecord& r : state.contact.records())
    if (r.row >= 0 && r.law.restitution > 0.0)
      state.bounces.push_back(
          solver::SoftSolver::Bounce{r.row, r.law.restitution, r.law.restitution_threshold});
  solver.restitution(state.bounces);
  toBodies();
  std::copy(solver.lambda().begin(), solver.lambda().end(), state.rows.lambda.begin());
  SolverReport report;
  report.rows = static_cast<int>(std::count(active.begin(), active.end(), std::uint8_t{1})) +
                joint_report.rows;
  report.iterations = n;
  report.residual = std::max(solver.residual(), joint_report.residual);
  report.redundant_rows = joint_report.redundant_rows;
  report.converged = report.residual <= settings.tolerance;
  return report;
}

/// store: the impulses, for the next pass's warm start and the contacts() report (the soft
/// step's: their sum over its substeps).
void storeImpulses(const Scene& scene, State& state, double h, bool soft) {
  const Rows& r = state.rows;
  // The soft step's joints stored theirs after each substep, and measured their loads there.
  if (!soft) {
    const auto joint_rows = std::span<const Row>(r.rows).first(r.joint_rows);
    state.joint_warm.store(joint_rows, r.lambda);
    state.joint_loads.measure(joint_rows, r.lambda, h, scene.joints, scene.bodies);
  }
  state.contact.store(scene.bodies, r.lambda, scene.threads,
                      soft ? state.soft.total() : std::span<const double>{});
}

/// positions: awake bodies take u+ and move by it, and by their split impulse's pseudo velocity.
void integratePositions(const Scene& scene, const State& state, double h) {
  eachBody(scene, [&](std::size_t i) {
    Body& b = scene.bodies[i];
    if (b.isStatic() || !awake(state, i) || accurate(state, i)) return;
    b.setLinearVelocity(state.solver_bodies[i].v);
    b.setAngularVelocity(state.solver_bodies[i].w);
    dynamics::integratePosition(b, h);
    if (i < state.island_work.push.size()) {  // the split impulse: positions only
      const PushVelocity& push = state.island_work.push[i];
      if (!push.v.isZero(0) || !push.w.isZero(0)) dynamics::displace(b, h * push.v, h * push.w);
    }
  });
}

/// stabilize: Newton iterations remove the joints' position errors (step/stabilization), as many as
/// `post_stabilization` (or `projection_iterations` with `projection` on); sleeping bodies, and
/// those the accurate integrator moved, are held where they are. `time`: the bodies' (the pass's
/// end).
void stabilize(const Scene& scene, State& state, double time) {
  const SolverSettings& settings = scene.settings.solver;
  const int iterations = settings.projection
                             ? std::max(settings.post_stabilization, settings.projection_iterations)
                             : settings.post_stabilization;
  if (iterations > 0 && !scene.joints.empty()) {
    std::vector<std::uint8_t>& frozen = state.may_sleep;  // scratch until the sleep stage
    frozen.resize(scene.bodies.size());
    bool any = false;  // a body to move (with all frozen, gathering the rows is all it would do)
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      frozen[i] = !awake(state, i) || accurate(state, i);
      any = any || (!frozen[i] && scene.bodies[i].isDynamic());
    }
    if (any)
      state.stabilization.run(scene.joints, scene.bodies, settings, iterations, frozen,
                              state.geometric_stiffness, time);
  }
  state.stabilization.endStep(scene.bodies);
}

/// track: each joint follows its history (a hinge counts turns).
void trackJoints(const Scene& scene) {
  const auto state = [&](BodyId id) { return stateOf(scene.bodies, id); };
  for (const auto& j : scene.joints) j->track(state(j->body1()), state(j->body2()));
}

/// sleep: islands resting on contacts whose bodies stayed slow long enough fall asleep, and their
/// bodies stop. Only islands with a contact row may sleep: a mechanism of joints alone keeps
/// moving however slowly it swings (a pendulum at 1 cm amplitude is below every rest threshold).
void sleep(const Scene& scene, State& state, double h) {
  const SleepSettings& settings = scene.settings.sleep;
  if (!settings.enabled) return;
  state.may_sleep.assign(static_cast<std::size_t>(state.islands.count()), 0);
  for (std::size_t k = state.rows.joint_rows; k < state.rows.rows.size(); ++k) {
    const int island = state.island_work.row_island[k];
    if (island >= 0) state.may_sleep[static_cast<std::size_t>(island)] = 1;
  }
  // Nor may an island that a moving kinematic body touches or holds: it would stay behind.
  const auto movingKinematic = [&](int body) {
    if (body < 0) return false;
    const Body& b = scene.bodies[static_cast<std::size_t>(body)];
    return b.isKinematic() && b.isMoving();
  };
  for (std::size_t k = 0; k < state.rows.rows.size(); ++k) {
    const Row& r = state.rows.rows[k];
    const int island = state.island_work.row_island[k];
    if (island < 0) continue;
    r.forEachBlock([&](int body, const Vec6&) {
      if (movingKinematic(body)) state.may_sleep[static_cast<std::size_t>(island)] = 0;
    });
  }
  // Nor may an island that the split impulse still pushes out of a penetration: it is not at
  // rest where it is, though the push leaves no velocity.
  const std::vector<PushVelocity>& push = state.island_work.push;
  for (std::size_t i = 0; i < push.size() && i < scene.bodies.size(); ++i) {
    const int island = state.islands.islandOf(static_cast<int>(i));
    if (island >= 0 && (!push[i].v.isZero(0) || !push[i].w.isZero(0)))
      state.may_sleep[static_cast<std::size_t>(island)] = 0;
  }
  state.sleep.update(state.islands, scene.bodies, h, settings, state.may_sleep);
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    Body& b = scene.bodies[i];
    if (awake(state, i) || b.isStatic()) continue;
    b.setLinearVelocity(Vec3::Zero());
    b.setAngularVelocity(Vec3::Zero());
  }
}

}  // namespace

SolverReport pass(const Scene& scene, State& state, double h) {
  state.island_work.push.clear();  // the split impulse's (the soft step's own: its last substep's)
  if (scene.settings.solver.type == SolverType::Soft) return softStep(scene, state, h);
  wakeDisturbed(scene, state);
  noteSetStates(scene, state);
  keepStartVelocities(scene.bodies, state.start_velocities);
  integrateVelocities(scene, state, h);
  collide(scene, state, h, scene.settings.contact);
  prepareRows(scene, state, h, h, true, true);
  const std::span<const std::uint8_t> island_awake =
      integrateAccurately(scene, state, buildIslands(scene, state, h), h, 0.5 * h);
  const SolverReport report = solve(scene, state, island_awake, h);
  storeImpulses(scene, state, h, false);
  integratePositions(scene, state, h);
  stabilize(scene, state, scene.time + h);
  trackJoints(scene);
  sleep(scene, state, h);
  keepLeftStates(scene, state);
  return report;
}

SolverReport softStep(const Scene& scene, State& state, double dt) {
  const int n = std::max(1, scene.settings.solver.substeps);
  wakeDisturbed(scene, state);
  noteSetStates(scene, state);
  // Soft contacts need no slop: the spring holds a resting contact still, at its whole depth.
  ContactSettings contacts = scene.settings.contact;
  contacts.slop = 0.0;
  collide(scene, state, dt, contacts);
  keepStartVelocities(scene.bodies, state.start_velocities);
  prepareRows(scene, state, dt / n, dt, false, false);
  const std::span<const std::uint8_t> island_awake =
      integrateAccurately(scene, state, buildIslands(scene, state, 0.0), dt,
                          0.5 * dt / std::max(1, scene.settings.solver.substeps));
  keepAccurateJointRows(state, state.accurate_rows, state.accurate_lambda);
  if (scene.settings.solver.post_stabilization > 0) state.stabilization.beginStep(scene.bodies);
  const SolverReport report = substeps(scene, state, island_awake, dt);
  if (!state.accurate_rows.empty())
    state.joint_loads.measure(state.accurate_rows, state.accurate_lambda, dt, scene.joints,
                              scene.bodies, true);
  storeImpulses(scene, state, dt, true);
  stabilize(scene, state, scene.time + dt);
  trackJoints(scene);
  sleep(scene, state, dt);
  keepLeftStates(scene, state);
  return report;
}

void wakeWithNeighbours(std::span<const Body> bodies, State& state, int index) {
  // A static body wakes only its neighbours.
  if (!bodies[static_cast<std::size_t>(index)].isStatic()) state.sleep.wake(index);
  state.neighbours.clear();
  state.contact.touching(index, state.neighbours);
  for (const int n : state.neighbours)
    if (!bodies[static_cast<std::size_t>(n)].isStatic()) state.sleep.wake(n);
}

}  // namespace linx::step
