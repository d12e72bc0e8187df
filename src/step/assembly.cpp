#include "step/assembly.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace linx::step {

BodyState stateOf(std::span<const Body> bodies, BodyId id) {
  if (id.isWorld()) return BodyState{};
  const Body& b = bodies[static_cast<std::size_t>(id.index)];
  return BodyState{b.pose(), b.linearVelocity(), b.angularVelocity()};
}

namespace {
BodyInertia inertiaOf(std::span<const Body> bodies, BodyId id) {
  if (id.isWorld()) return {};
  const Body& b = bodies[static_cast<std::size_t>(id.index)];
  if (b.isStatic()) return {};
  return BodyInertia{b.inverseMass(), b.inverseInertiaWorld()};
}
}  // namespace

void keepStartVelocities(std::span<const Body> bodies, std::vector<StartVelocity>& start) {
  start.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i)
    start[i] = StartVelocity{bodies[i].linearVelocity(), bodies[i].angularVelocity()};
}

JointContext contextOf(std::span<const Body> bodies, const Joint& j, const SolverSettings& settings,
                       double h, double time, std::span<const StartVelocity> start) {
  const JointDef& def = j.def();
  JointContext ctx{stateOf(bodies, j.body1()), stateOf(bodies, j.body2()), h,
                   def.erp.value_or(settings.erp), def.cfm.value_or(settings.cfm)};
  ctx.time = time;
  const std::array<BodyId, 2> more = j.coupledBodies();
  for (std::size_t i = 0; i < more.size(); ++i)
    if (!more[i].isWorld()) ctx.more[i] = stateOf(bodies, more[i]);
  // Only armature reads the velocities at the start.
  const auto armature = [](const CoordinateDef& c) { return c.armature > 0.0; };
  if (!start.empty() && std::any_of(def.coordinates.begin(), def.coordinates.end(), armature)) {
    const auto at = [&](BodyId id, const BodyState& now) {
      BodyState s = now;
      if (!id.isWorld()) {
        s.v = start[static_cast<std::size_t>(id.index)].v;
        s.w = start[static_cast<std::size_t>(id.index)].w;
      }
      return s;
    };
    ctx.start = std::pair{at(j.body1(), ctx.b1), at(j.body2(), ctx.b2)};
  }
  // Only drives (servos, springs) and friction read the inertia: the others skip rotating it to the
  // world.
  const auto drives = [](const CoordinateDef& c) {
    return c.spring || (c.motor && c.motor->isServo()) || c.friction > 0.0 || c.armature > 0.0;
  };
  if (std::any_of(def.coordinates.begin(), def.coordinates.end(), drives)) {
    ctx.m1 = inertiaOf(bodies, j.body1());
    ctx.m2 = inertiaOf(bodies, j.body2());
  }
  return ctx;
}

namespace {
int solverIndex(std::span<const Body> bodies, BodyId id) {
  if (id.isWorld() || bodies[static_cast<std::size_t>(id.index)].isStatic()) return -1;
  return id.index;
}
bool finite(const Row& r) {
  return r.Ja.allFinite() && r.Jb.allFinite() && r.Jc.allFinite() && r.Jd.allFinite() &&
         std::isfinite(r.phi) && std::isfinite(r.speed) && std::isfinite(r.erp) &&
         std::isfinite(r.cfm) && !std::isnan(r.lo) && !std::isnan(r.hi);
}

/// A coupled row's blocks c and d on their bodies (solver indices), each folded into the block of
/// the same body when a and b (or c) have it: a row's bodies are distinct.
void placeCoupled(Row& r, int c, int d) {
  const auto place = [&](int body, Vec6& j, int& index) {
    if (body < 0) {
      index = -1;
    } else if (body == r.body_a) {
      r.Ja += j;
      index = -1;
    } else if (body == r.body_b) {
      r.Jb += j;
      index = -1;
    } else if (&j == &r.Jd && body == r.body_c) {
      r.Jc += j;
      index = -1;
    } else {
      index = body;
      return;
    }
    j.setZero();
  };
  place(c, r.Jc, r.body_c);
  place(d, r.Jd, r.body_d);
}
}  // namespace

int fillJoint(std::span<const std::unique_ptr<Joint>> joints, std::size_t ji,
              std::span<const Body> bodies, const JointContext& ctx, std::span<Row> slots) {
  const Joint& j = *joints[ji];
  for (Row& r : slots) r = Row{.erp = ctx.erp, .cfm = ctx.cfm};
  const int a = solverIndex(bodies, j.body1()), b = solverIndex(bodies, j.body2());
  const std::array<BodyId, 2> more = j.coupledBodies();
  const int c = solverIndex(bodies, more[0]), d = solverIndex(bodies, more[1]);
  if (a < 0 && b < 0 && c < 0 && d < 0) return 0;  // between static bodies: nothing can move
  const int n = j.fill(ctx, slots);
  if (n < 0 || n > j.maxRows())
    throw std::logic_error(fmt::format("joints[{}] ({}): wrote {} rows, more than its maxRows() {}",
                                       ji, j.name(), n, j.maxRows()));
  for (int k = 0; k < n; ++k) {
    Row& r = slots[static_cast<std::size_t>(k)];
    r.body_a = a;
    r.body_b = b;
    if (c >= 0 || d >= 0) placeCoupled(r, c, d);
    r.key = (static_cast<std::uint64_t>(ji + 1) << 8) | (r.key & 0xff);
    if (r.normal >= n)
      throw std::logic_error(fmt::format("joints[{}] ({}): friction row refers to row {} of {}", ji,
                                         j.name(), r.normal, n));
    if (!finite(r))
      throw std::domain_error(
          fmt::format("joints[{}] ({}): its constraint rows are not finite (degenerate geometry, "
                      "or masses, forces or speeds too large for a double)",
                      ji, j.name()));
  }
  return n;
}

void assembleRows(std::span<const std::unique_ptr<Joint>> joints, std::span<const Body> bodies,
                  const SolverSettings& settings, double h, double time, std::vector<Row>& rows,
                  std::span<const StartVelocity> start) {
  // 1. count
  std::size_t capacity = 0;
  for (const auto& j : joints)
    if (j->enabled()) capacity += static_cast<std::size_t>(j->maxRows());
  // 2. allocate (the vector keeps its capacity across steps: no allocation after warm-up)
  rows.resize(capacity);
  // 3. fill and 4. verify, joint by joint
  std::size_t used = 0;
  for (std::size_t ji = 0; ji < joints.size(); ++ji) {
    const Joint& j = *joints[ji];
    if (!j.enabled()) continue;  // broken or switched off: no rows
    const auto slots = std::span<Row>(rows).subspan(used, static_cast<std::size_t>(j.maxRows()));
    const int n =
        fillJoint(joints, ji, bodies, contextOf(bodies, j, settings, h, time, start), slots);
    // A friction row's normal row: its index from the joint's to the list's.
    for (Row& r : slots.first(static_cast<std::size_t>(n)))
      if (r.normal >= 0) r.normal += static_cast<int>(used);
    used += static_cast<std::size_t>(n);
  }
  rows.resize(used);
}

}  // namespace linx::step
