// linx built from a bench::Scene through its public API, exactly as a user would.
#include "../engine.hpp"

#include <linx/linx.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <thread>
#include <utility>

namespace bench {
namespace {

linx::ShapeDef shapeOf(const Shape& s, double friction) {
  linx::ShapeDef d;
  switch (s.kind) {
    case Shape::Kind::Sphere:
      d.type = linx::ShapeType::Sphere;
      d.radius = s.radius;
      break;
    case Shape::Kind::Box:
      d.type = linx::ShapeType::Box;
      d.size = 2.0 * s.half_extents;
      break;
    case Shape::Kind::Capsule:
      d.type = linx::ShapeType::Capsule;
      d.radius = s.radius;
      d.length = 2.0 * s.half_length;
      break;
    case Shape::Kind::None:
      break;
  }
  d.friction = friction;
  return d;
}

class LinxEngine final : public Engine {
 public:
  LinxEngine(const Scene& scene, const linx::SolverSettings& solver, int threads,
             const linx::IntegratorSettings& integrator = {}) {
    linx::WorldSettings settings;
    settings.integrator = integrator;
    settings.gravity = scene.gravity;
    settings.timestep = scene.timestep;
    settings.solver = solver;
    settings.threads = threads;
    world_ = linx::World(settings);
    ids_.reserve(scene.bodies.size());
    for (const Body& b : scene.bodies) {
      linx::BodyDef def{.name = b.name,
                        .mass = b.mass,
                        .inertia = linx::Mat3(b.inertia.asDiagonal()),
                        .position = b.position,
                        .orientation = b.orientation,
                        .linear_velocity = b.velocity,
                        .angular_velocity = b.angular_velocity,
                        .is_static = b.is_static,
                        .shapes = {}};
      if (b.shape.kind != Shape::Kind::None) def.shapes.push_back(shapeOf(b.shape, scene.friction));
      ids_.push_back(world_.createBody(def));
    }
    if (scene.ground_z) {
      linx::ShapeDef plane;
      plane.type = linx::ShapeType::Plane;
      plane.normal = Vec3::UnitZ();
      plane.offset = *scene.ground_z;
      plane.friction = scene.friction;
      linx::BodyDef ground;
      ground.name = "ground";
      ground.is_static = true;
      ground.shapes.push_back(plane);
      world_.createBody(ground);
    }
    for (const Joint& j : scene.joints) {
      // linx's body1 must be a body; a joint to the world names the world as body2. Swapping the
      // bodies turns the coordinate's sign, so limits and motor turn with it.
      const bool swap = j.body1 < 0;
      const int b1 = swap ? j.body2 : j.body1, b2 = swap ? j.body1 : j.body2;
      const double sign = swap ? -1.0 : 1.0;
      linx::JointDef def;
      def.name = std::to_string(world_.jointCount()).insert(0, "joint");
      def.body1 = ids_[b1];
      def.body2 = b2 < 0 ? linx::kWorldBody : ids_[b2];
      def.anchor = j.anchor;
      def.axis = j.axis;
      if (j.limits) {
        const double lo = sign * j.limits->lower, hi = sign * j.limits->upper;
        def.coordinates[0].limits = linx::JointLimits{std::min(lo, hi), std::max(lo, hi)};
      }
      if (j.motor)
        def.coordinates[0].motor =
            linx::JointMotor{sign * j.motor->target_velocity, j.motor->max_force};
      world_.createJoint(typeName(j.kind), def);
    }
    for (const Spring& sp : scene.springs) {  // linx's spring joint: body1 must be a body
      const bool swap = sp.body1 < 0;
      linx::JointDef def;
      def.name = std::to_string(world_.jointCount()).insert(0, "spring");
      def.body1 = ids_[swap ? sp.body2 : sp.body1];
      const int other = swap ? sp.body1 : sp.body2;
      def.body2 = other < 0 ? linx::kWorldBody : ids_[other];
      def.anchor = swap ? sp.anchor2 : sp.anchor1;
      def.anchor2 = swap ? sp.anchor1 : sp.anchor2;
      def.coordinates[0].spring = linx::JointSpring{sp.stiffness, sp.damping, sp.rest};
      world_.createJoint("spring", def);
    }
  }

  void step() override { world_.step(); }
  std::size_t contactCount() const override { return world_.contacts().size(); }
  Pose pose(int i) const override {
    const linx::Body& b = world_.body(ids_[i]);
    return {b.position(), b.orientation()};
  }
  Twist velocity(int i) const override {  // linx's body frame is the centre of mass's
    const linx::Body& b = world_.body(ids_[i]);
    return {b.linearVelocity(), b.angularVelocity()};
  }

 private:
  static const char* typeName(Joint::Kind kind) {
    switch (kind) {
      case Joint::Kind::Hinge:
        return "hinge";
      case Joint::Kind::Slider:
        return "slider";
      case Joint::Kind::Ball:
        return "ball";
      case Joint::Kind::Fixed:
        return "fixed";
    }
    return "?";
  }

  linx::World world_;
  std::vector<linx::BodyId> ids_;
};

bool hasContacts(const Scene& scene) {
  if (scene.ground_z) return true;
  for (const Body& b : scene.bodies) {
    if (b.shape.kind != Shape::Kind::None) return true;
  }
  return false;
}

}  // namespace

namespace {

/// A linx row: the step's knobs (integrator "step", whatever the default), unless `integrator`
/// says otherwise.
Variant variant(std::string settings, const linx::SolverSettings& solver, bool reference,
                int threads = 1,
                linx::IntegratorSettings integrator = {.type = linx::IntegratorType::Step}) {
  return Variant{"linx", std::move(settings),
                 [solver, threads, integrator](const Scene& s) -> std::unique_ptr<Engine> {
                   return std::make_unique<LinxEngine>(s, solver, threads, integrator);
                 },
                 reference, threads};
}

/// The reference row: linx's defaults, one thread. With contacts every island takes the step
/// (the default integrator "auto" gives the accurate one islands of joints alone). With `threads`
/// above one, the same defaults on that many threads, checked against the reference row to the
/// bit: only the thread count may differ between the two (the integrator too once made ragdolls,
/// whose islands of joints alone "auto" gives the accurate integrator, differ from step 1).
Variant defaultRow(const Scene& scene, int threads = 1) {
  const linx::SolverSettings defaults;
  const bool contacts = hasContacts(scene);
  std::string settings = contacts
                             ? "default: auto (PGS on friction islands, " +
                                   std::to_string(defaults.iterations) + " it max)"
                             : "default: integrator auto, solver auto (exact, post-stabilization " +
                                   std::to_string(defaults.post_stabilization) + " it)";
  if (threads > 1) settings += ", " + std::to_string(threads) + " threads";
  Variant v =
      variant(std::move(settings), defaults, threads == 1, threads, linx::IntegratorSettings{});
  v.knob = contacts
               ? "default step: auto (PGS, " + std::to_string(defaults.iterations) + " sweeps max)"
               : "default: integrator auto";
  return v;
}

/// A mechanism's step at its default solver: what "auto" gives islands it cannot hold.
Variant defaultStep() {
  const linx::SolverSettings defaults;
  Variant v = variant("integrator step, solver auto (exact, post-stabilization " +
                          std::to_string(defaults.post_stabilization) + " it)",
                      defaults, false);
  v.knob = "integrator step, default solver";
  return v;
}

/// The soft step (docs/solver.md): rows prepared once, `substeps` substeps of one sweep each.
Variant softStep(int substeps, int threads = 1) {
  linx::SolverSettings soft;
  soft.type = linx::SolverType::Soft;
  soft.substeps = substeps;
  std::string settings("soft step, ");
  settings += std::to_string(substeps);
  settings += substeps == 1 ? " substep" : " substeps";
  if (threads > 1) settings += ", " + std::to_string(threads) + " threads";
  Variant v = variant(settings, soft, false, threads);
  std::string knob("soft step, SolverSettings::substeps = ");
  knob += std::to_string(substeps);
  v.knob = std::move(knob);
  return v;
}

}  // namespace

std::vector<Variant> linxVariants(const Scene& scene) {
  const linx::SolverSettings defaults;
  std::vector<Variant> out;
  out.push_back(defaultRow(scene));
  if (hasContacts(scene)) {
    // The same on every hardware thread: the same results to the bit, in less time.
    const int cores = static_cast<int>(std::thread::hardware_concurrency());
    if (cores > 1) out.push_back(defaultRow(scene, cores));
    out.push_back(softStep(4));
    if (cores > 1) {  // its sweeps split over the threads by colour
      Variant threaded = softStep(4, cores);
      threaded.one_thread = out.back().settings;
      out.push_back(std::move(threaded));
    }
    return out;
  }
  // Mechanisms: the step at the default solver (exact, then the joints' post-stabilization),
  // without the post-stabilization (error reduction alone), with more of its iterations, and with
  // substeps for stiff chains.
  out.push_back(defaultStep());
  linx::SolverSettings erp_only = defaults;
  erp_only.post_stabilization = 0;
  out.push_back(variant("exact, ERP 0.2 only", erp_only, false));
  linx::SolverSettings more = defaults;
  more.post_stabilization = 8;
  out.push_back(variant("post-stabilization 8 it", more, false));
  linx::SolverSettings substepped = defaults;
  substepped.substeps = 4;
  out.push_back(variant("default, 4 substeps", substepped, false));
  return out;
}

// The integrator table: the step at its defaults, and the accurate integrator at four tolerances,
// its default (1e-10) the reference row.
std::vector<Variant> linxIntegrators(const Scene& scene) {
  std::vector<Variant> out;
  Variant step = defaultStep();
  step.knob = "step";
  out.push_back(std::move(step));
  Variant automatic = defaultRow(scene);
  automatic.reference = false;
  automatic.knob = "auto (default)";
  out.push_back(std::move(automatic));
  // "auto" at a looser tolerance: one accurate step a frame holds it on more frames.
  for (double tolerance : {1e-8, 1e-6}) {
    const linx::IntegratorSettings loose{.type = linx::IntegratorType::Auto,
                                         .tolerance = tolerance};
    const std::string label = fmt::format("auto, tolerance {:g}", tolerance);
    Variant v = variant("integrator: " + label, linx::SolverSettings{}, false, 1, loose);
    v.knob = label;
    out.push_back(std::move(v));
  }
  const linx::IntegratorSettings defaults{.type = linx::IntegratorType::Accurate};
  for (double tolerance : {1e-6, 1e-8, 1e-10, 1e-12}) {
    linx::IntegratorSettings accurate = defaults;
    accurate.tolerance = tolerance;
    const bool is_default = tolerance == defaults.tolerance;
    const std::string label =
        fmt::format("accurate, tolerance {:g}{}", tolerance, is_default ? " (the default's)" : "");
    Variant v{"linx", "integrator: " + label,
              [accurate](const Scene& s) -> std::unique_ptr<Engine> {
                return std::make_unique<LinxEngine>(s, linx::SolverSettings{}, 1, accurate);
              },
              is_default};
    v.knob = label;
    out.push_back(std::move(v));
  }
  return out;
}

std::vector<Variant> linxSweep(const Scene& scene, const std::vector<int>& counts) {
  std::vector<Variant> out{defaultRow(scene)};
  for (int substeps : counts) out.push_back(softStep(substeps));
  return out;
}

}  // namespace bench
