#include "step/step.hpp"

#include "dynamics/integrator.hpp"
#include "parallel/parallel_for.hpp"
#include "step/assembly.hpp"
#include "step/projection.hpp"

#include <algorithm>

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
/// bodies it touched (its island follows at the islands stage).
void wakeDisturbed(const Scene& scene, State& state) {
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const Body& b = scene.bodies[i];
    if (!awake(state, i) && (!b.linearVelocity().isZero(0) || !b.angularVelocity().isZero(0) ||
                             !b.force().isZero(0) || !b.torque().isZero(0)))
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
void collide(const Scene& scene, State& state, double h) {
  state.contact.detect(scene.bodies, scene.joints, scene.settings.contact, h, scene.threads);
}

/// prepare: the joints' rows, then three rows per contact point, each with its warm start.
void prepareRows(const Scene& scene, State& state, double h) {
  const SolverSettings& solver = scene.settings.solver;
  Rows& r = state.rows;
  assembleRows(scene.joints, scene.bodies, solver, h, r.rows);
  r.joint_rows = r.rows.size();
  r.lambda.assign(r.joint_rows, 0.0);
  if (solver.warm_start) state.joint_warm.load(r.rows, r.lambda);
  state.contact.appendRows(scene.bodies, h, r.rows, r.lambda, solver.warm_start, scene.threads);
}

/// islands: bodies linked by this pass's rows. With sleeping on, an island with an awake body
/// wakes entirely, and the bodies it wakes get this pass's velocity update; with it off, every
/// body is awake. Returns one awake flag per island (empty: all awake).
std::span<const std::uint8_t> buildIslands(const Scene& scene, State& state, double h) {
  rowLinks(state.rows.rows, state.links);
  const std::size_t n = scene.bodies.size();
  state.movable.resize(n);
  for (std::size_t i = 0; i < n; ++i) state.movable[i] = !scene.bodies[i].isStatic();
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
  for (std::size_t i = 0; i < n; ++i)
    if (was_asleep[i] && awake(state, i))
      dynamics::integrateVelocity(scene.bodies[i], scene.settings.gravity, h);
  return island_awake;
}

/// solve: gathers the compact solver bodies (u*), solves every awake island with the world's
/// solver; the solver bodies then hold u+ and the rows' impulses lambda. Sleeping islands keep
/// the impulses they rest on, for when they wake.
SolverReport solve(const Scene& scene, State& state, std::span<const std::uint8_t> island_awake,
                   double h) {
  state.solver_bodies.resize(scene.bodies.size());
  eachBody(scene, [&](std::size_t i) {
    const Body& b = scene.bodies[i];
    state.solver_bodies[i] = solver::SolverBody{b.inverseMass(), b.inverseInertiaWorld(),
                                                b.linearVelocity(), b.angularVelocity()};
  });
  const SolverSettings& settings = scene.settings.solver;
  if (!state.solver || state.solver_type != settings.type) {
    state.solver = solver::makeSolver(settings.type);
    state.solver_type = settings.type;
  }
  return solveIslands(state.islands, island_awake, state.rows.rows, state.solver_bodies,
                      state.rows.lambda, h, *state.solver, settings, state.island_work,
                      scene.threads);
}

/// store: the impulses, for the next pass's warm start and the contacts() report.
void storeImpulses(const Scene& scene, State& state) {
  const Rows& r = state.rows;
  state.joint_warm.store(std::span<const Row>(r.rows).first(r.joint_rows), r.lambda);
  state.contact.store(scene.bodies, r.lambda, scene.threads);
}

/// positions: awake bodies take u+ and move by it.
void integratePositions(const Scene& scene, const State& state, double h) {
  eachBody(scene, [&](std::size_t i) {
    Body& b = scene.bodies[i];
    if (b.isStatic() || !awake(state, i)) return;
    b.setLinearVelocity(state.solver_bodies[i].v);
    b.setAngularVelocity(state.solver_bodies[i].w);
    dynamics::integratePosition(b, h);
  });
}

/// project: with `projection` on, Newton iterations pull the joints' position errors back;
/// sleeping bodies are held where they are.
void project(const Scene& scene, State& state) {
  if (!scene.settings.solver.projection) return;
  std::vector<std::uint8_t>& frozen = state.may_sleep;  // scratch until the sleep stage
  frozen.resize(scene.bodies.size());
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) frozen[i] = !awake(state, i);
  projectPositions(scene.joints, scene.bodies, scene.settings.solver, frozen);
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
  wakeDisturbed(scene, state);
  integrateVelocities(scene, state, h);
  collide(scene, state, h);
  prepareRows(scene, state, h);
  const std::span<const std::uint8_t> island_awake = buildIslands(scene, state, h);
  const SolverReport report = solve(scene, state, island_awake, h);
  storeImpulses(scene, state);
  integratePositions(scene, state, h);
  project(scene, state);
  trackJoints(scene);
  sleep(scene, state, h);
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
