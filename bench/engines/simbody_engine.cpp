// Simbody 3.7 (Debian libsimbody-dev) adapter, for the integrator table only (linx-bench
// --integrators): mechanisms without contacts, integrated by Simbody's error-controlled
// integrators, RungeKuttaMersonIntegrator at accuracies 1e-6, 1e-8 and 1e-10 and CPodesIntegrator
// (BDF, Newton iteration) at 1e-8.
//
// Simbody works in internal (mobilizer) coordinates, so the scene becomes a tree of
// MobilizedBodies, built from buildSceneTree (scene_tree.hpp, the spanning forest MuJoCo's and
// DART's adapters use too):
// - every body's frame is the scene body's principal frame, its origin at the centre of mass
//   (MassProperties(mass, 0, Inertia(principal moments))), so pose() is the body frame's pose;
// - a tree joint becomes a mobilizer from the parent (Ground for the world) to the child: a hinge a
//   MobilizedBody::Pin (rotation about the common Z of its frames F and M), a slider a
//   MobilizedBody::Slider (translation along their X), a ball a MobilizedBody::Ball, a fixed joint
//   a MobilizedBody::Weld. F (on the parent) and M (on the child) both sit at the joint's anchor
//   with the same world orientation at creation (Z, or X for a slider, along the joint axis; the
//   world's axes for a ball or weld), so at q = 0 every body is at its scene pose. When the tree
//   edge runs from body2 to body1 the axis is negated, so the mobilizer's coordinate is the
//   scene's (body2 relative to body1). A dynamic body without a joint path to the world gets a
//   MobilizedBody::Free from Ground, F at its scene pose.
// - a joint that closes a loop becomes constraints: a hinge a Constraint::Ball at its anchor, plus
//   a second one 0.1 m along its axis unless the tree already keeps the two bodies' relative
//   rotation about that axis (rotationKeptAbout, as in the planar four-bars); a ball a
//   Constraint::Ball. In the planar IFToMM A02 every ball's out-of-plane row is redundant:
//   Simbody's projections and multiplier solve are least-squares (pseudoinverse) solutions, which
//   accept that. They also drop rows whose singular values fall below a conditioning tolerance
//   (m sqrt(eps) for m rows), which happens near A02's singular positions (cranks horizontal):
//   the velocity error along those rows then grows and cannot be projected out, every trial step
//   fails its velocity projection, and the integrator halves its step down to zero and throws
//   ("Unable to advance time past ..."): the run fails with that note. (Projecting after every
//   step, setProjectEveryStep(true), which is not Simbody's default, got RK Merson at 1e-8
//   through A02's 20 s, 9e-5 m from the published positions, in 160 s.)
// - gravity is a Force::UniformGravity (GeneralForceSubsystem); a spring a
//   Force::TwoPointLinearSpring and a Force::TwoPointLinearDamper between its points; nothing else
//   acts.
// - initial velocities: each mobilizer's u is fitted to the child's spatial velocity relative to
//   its parent at the joint, in F (setUToFit*Velocity); then the state is projected onto the
//   constraints (System::project) and the bodies' velocities are checked against the scene's.
// Refused (Unsupported): contacts (shapes, the ground), static bodies, joint limits and motors,
// slider or fixed joints that close loops.
//
// Integration: Simbody's accuracy is a relative tolerance on each step's local error estimate, in
// an RMS norm over the state (each u's error relative to max(|u|, 1), in rad/s or m/s: Simbody's
// unit weights; each q's through the same weights), not a bound on the global error. The
// constraint tolerance is Simbody's default relationship, accuracy / 10, set explicitly: the RMS of
// the position and velocity constraint errors in m and m/s (their unit weights are 1 here). After
// a step Simbody projects the state onto the constraints when their error exceeds that tolerance
// (aiming at a tenth of it), and the step fails when the projection cannot reach it (its default;
// setProjectEveryStep is left off). step() calls Integrator::stepTo(t_next) with interpolation
// disabled (setAllowInterpolation(false)): the integrator shortens its last internal step to end
// exactly at t_next, so the state that pose() reads is a step of the trajectory, not a cubic
// Hermite interpolation between internal steps (what stepTo returns by default). An internal step
// therefore never spans two scene steps, which caps the step size at h. stepTo returns without
// advancing on its first call (StartOfContinuousInterval), and CPodes returns after its internal
// step limit (ReachedStepLimit), so step() calls it until t_next is reached, and reports a failure
// when a call makes no progress. A state that becomes non-finite stops the engine: pose() and
// velocity() then report NaN. Any other Simbody exception fails the run, its message as the note.
//
// Simbody 3.7's headers do not compile as C++20 (bench/CMakeLists.txt): this file is C++17.
#include "engine.hpp"
#include "scene_tree.hpp"

#include <Simbody.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace bench {
namespace {

// Distance along a loop-closing hinge's axis of its second ball constraint (m).
constexpr double kSecondBallOffset = 0.1;
// Initial velocities: the largest difference (m/s, rad/s) between the bodies' velocities after the
// fit and projection and the scene's (round-off on consistent initial conditions).
constexpr double kVelocityFitTolerance = 1e-9;

// Internal steps after which Integrator::stepTo returns (ReachedStepLimit; CPodes's default is 500
// and prints an error each time): a call that reaches it having advanced less than kStall times the
// scene's timestep has stalled. It does not change the integration.
constexpr int kInternalStepLimit = 100;
constexpr double kStall = 1e-9;
// Calls of Integrator::stepTo within one scene step after which the time must have advanced by
// kStall of the step.
constexpr int kStallCalls = 10;

enum class Method { Merson, CPodesBdf };

/// One row of the table.
struct Options {
  Method method = Method::Merson;
  double accuracy = 1e-8;
};

SimTK::Vec3 toSimTK(const Vec3& v) {
  return SimTK::Vec3(v.x(), v.y(), v.z());
}
Vec3 fromSimTK(const SimTK::Vec3& v) {
  return Vec3(v[0], v[1], v[2]);
}
SimTK::Rotation toSimTK(const Quat& q) {
  return SimTK::Rotation(SimTK::Quaternion(q.w(), q.x(), q.y(), q.z()));
}

/// Throws Unsupported for what this adapter does not model.
void checkScene(const Scene& scene) {
  if (scene.ground_z) throw Unsupported("contacts (a ground plane) are not mapped to Simbody");
  for (const Body& b : scene.bodies) {
    if (b.is_static) throw Unsupported("static bodies are not mapped to Simbody");
    if (b.shape.kind != Shape::Kind::None)
      throw Unsupported("contacts (collision shapes) are not mapped to Simbody");
  }
  for (const Joint& j : scene.joints) {
    if (j.limits || j.motor) throw Unsupported("joint limits and motors are not mapped to Simbody");
  }
}

/// The world orientation of a joint's frames F and M at creation: Z along a hinge's axis, X along
/// a slider's (negated when the tree edge runs from body2 to body1), the world's otherwise.
Quat jointFrame(const Joint& jt, bool flipped) {
  const Vec3 axis = (flipped ? -jt.axis : jt.axis).normalized();
  switch (jt.kind) {
    case Joint::Kind::Hinge:
      return Quat::FromTwoVectors(Vec3::UnitZ(), axis);
    case Joint::Kind::Slider:
      return Quat::FromTwoVectors(Vec3::UnitX(), axis);
    case Joint::Kind::Ball:
    case Joint::Kind::Fixed:
      break;
  }
  return Quat::Identity();
}

/// A frame given in the world (orientation q, origin at point) in body b's frame (nullptr: Ground).
SimTK::Transform frameIn(const Body* b, const Quat& q, const Vec3& point) {
  if (!b) return SimTK::Transform(toSimTK(q), toSimTK(point));
  const Quat bq = b->orientation.normalized();
  return SimTK::Transform(toSimTK(bq.conjugate() * q),
                          toSimTK(bq.conjugate() * (point - b->position)));
}

/// A world point in body b's frame (nullptr: Ground).
SimTK::Vec3 pointIn(const Body* b, const Vec3& point) {
  if (!b) return toSimTK(point);
  return toSimTK(b->orientation.normalized().conjugate() * (point - b->position));
}

/// The velocity (world) of the material point of body b (nullptr: the world) at `point`.
Vec3 pointVelocity(const Body* b, const Vec3& point) {
  if (!b) return Vec3::Zero();
  return b->velocity + b->angular_velocity.cross(point - b->position);
}

/// Simbody's exception messages span lines: "SimTK Exception thrown at File.cpp:123:", the message,
/// "(Required condition '...' was not met.)", nested for a failed step. The message lines, as one
/// line for the table's note.
std::string oneLine(const std::string& what) {
  std::string out;
  std::istringstream lines(what);
  for (std::string line; std::getline(lines, line);) {
    const std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos) continue;
    line.erase(0, start);
    if (line.rfind("SimTK Exception thrown at", 0) == 0 ||
        line.rfind("(Required condition", 0) == 0)
      continue;
    if (!out.empty()) out += ' ';
    out += line;
  }
  return "Simbody: " + out;
}

bool allFinite(const SimTK::Vector& y) {
  for (int k = 0; k < y.size(); ++k)
    if (!std::isfinite(y[k])) return false;
  return true;
}

std::string methodName(Method method) {
  return method == Method::Merson ? "RK Merson" : "CPodes BDF";
}

class SimbodyEngine final : public Engine {
 public:
  SimbodyEngine(const Scene& scene, const Options& options);
  void step() override;
  Pose pose(int i) const override;
  Twist velocity(int i) const override;

 private:
  const Body* bodyOf(int i) const {
    return i == kWorld ? nullptr : &scene_.bodies[static_cast<std::size_t>(i)];
  }
  SimTK::MobilizedBody& mobilizedBody(int i) {
    return i == kWorld ? matter_.updGround()
                       : matter_.updMobilizedBody(mobod_[static_cast<std::size_t>(i)]);
  }
  void addMobilizer(int i);
  void addClosure(int j);
  void fitVelocity(int i, SimTK::State& state) const;
  void checkVelocities(const SimTK::State& state) const;
  void advanceTowards(double t);
  void startIntegrator(const Options& options, const SimTK::State& state);

  const Scene scene_;  ///< a copy, for the construction
  SceneTree tree_;
  SimTK::MultibodySystem system_;
  SimTK::SimbodyMatterSubsystem matter_;
  SimTK::GeneralForceSubsystem forces_;
  std::vector<SimTK::MobilizedBodyIndex> mobod_;  ///< of Scene::bodies[i]
  std::vector<Quat> frame_;                       ///< world orientation of body i's F at creation
  std::unique_ptr<SimTK::Integrator> integ_;      ///< declared after the system it refers to
  double h_ = 0.0;
  long steps_ = 0;
  bool diverged_ = false;
};

SimbodyEngine::SimbodyEngine(const Scene& scene, const Options& options)
    : scene_(scene),
      tree_(buildSceneTree(scene, false)),
      matter_(system_),
      forces_(system_),
      mobod_(scene.bodies.size()),
      frame_(scene.bodies.size(), Quat::Identity()),
      h_(scene.timestep) {
  // Parents before children: breadth first from the roots.
  std::vector<int> order(tree_.roots.begin(), tree_.roots.end());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto& children = tree_.children[static_cast<std::size_t>(order[k])];
    order.insert(order.end(), children.begin(), children.end());
  }
  for (int i : order) addMobilizer(i);
  for (int j : tree_.closures) addClosure(j);
  SimTK::Force::UniformGravity(forces_, matter_, toSimTK(scene.gravity));
  for (const Spring& sp : scene.springs) {  // the tension k (d - rest) + c d' as two elements
    SimTK::MobilizedBody& b1 = mobilizedBody(sp.body1);
    SimTK::MobilizedBody& b2 = mobilizedBody(sp.body2);
    const SimTK::Vec3 s1 = pointIn(bodyOf(sp.body1), sp.anchor1);
    const SimTK::Vec3 s2 = pointIn(bodyOf(sp.body2), sp.anchor2);
    if (sp.stiffness > 0.0)
      SimTK::Force::TwoPointLinearSpring(forces_, b1, s1, b2, s2, sp.stiffness, sp.rest);
    if (sp.damping > 0.0) SimTK::Force::TwoPointLinearDamper(forces_, b1, s1, b2, s2, sp.damping);
  }

  system_.realizeTopology();
  SimTK::State state = system_.getDefaultState();  // q = 0: the scene's poses
  system_.realize(state, SimTK::Stage::Position);
  for (int i : order) fitVelocity(i, state);
  system_.project(state, 1e-12);  // loops: positions and velocities onto the constraints
  checkVelocities(state);
  startIntegrator(options, state);
}

/// Body i's mobilizer from its tree parent (Ground for the world or a free root).
void SimbodyEngine::addMobilizer(int i) {
  const auto ii = static_cast<std::size_t>(i);
  const Body& b = scene_.bodies[ii];
  const SimTK::Body::Rigid body(SimTK::MassProperties(
      b.mass, SimTK::Vec3(0), SimTK::Inertia(b.inertia.x(), b.inertia.y(), b.inertia.z())));
  if (tree_.free_root[ii]) {
    frame_[ii] = b.orientation.normalized();
    mobod_[ii] =
        SimTK::MobilizedBody::Free(matter_.updGround(), frameIn(nullptr, frame_[ii], b.position),
                                   body, SimTK::Transform())
            .getMobilizedBodyIndex();
    return;
  }
  const Joint& jt = scene_.joints[static_cast<std::size_t>(tree_.joint[ii])];
  frame_[ii] = jointFrame(jt, tree_.flipped[ii]);
  const int p = tree_.parent[ii];
  SimTK::MobilizedBody& parent = mobilizedBody(p);
  const SimTK::Transform X_PF = frameIn(bodyOf(p), frame_[ii], jt.anchor);
  const SimTK::Transform X_BM = frameIn(&b, frame_[ii], jt.anchor);
  switch (jt.kind) {
    case Joint::Kind::Hinge:
      mobod_[ii] = SimTK::MobilizedBody::Pin(parent, X_PF, body, X_BM).getMobilizedBodyIndex();
      return;
    case Joint::Kind::Slider:
      mobod_[ii] = SimTK::MobilizedBody::Slider(parent, X_PF, body, X_BM).getMobilizedBodyIndex();
      return;
    case Joint::Kind::Ball:
      mobod_[ii] = SimTK::MobilizedBody::Ball(parent, X_PF, body, X_BM).getMobilizedBodyIndex();
      return;
    case Joint::Kind::Fixed:
      mobod_[ii] = SimTK::MobilizedBody::Weld(parent, X_PF, body, X_BM).getMobilizedBodyIndex();
      return;
  }
}

/// A loop-closing joint as ball constraints (one, or two along a hinge's axis).
void SimbodyEngine::addClosure(int j) {
  const Joint& jt = scene_.joints[static_cast<std::size_t>(j)];
  if (jt.kind == Joint::Kind::Slider || jt.kind == Joint::Kind::Fixed)
    throw Unsupported("a slider or fixed joint closing a loop is not mapped to Simbody");
  const auto ball = [&](const Vec3& point) {
    SimTK::Constraint::Ball(mobilizedBody(jt.body1), pointIn(bodyOf(jt.body1), point),
                            mobilizedBody(jt.body2), pointIn(bodyOf(jt.body2), point));
  };
  ball(jt.anchor);
  if (jt.kind == Joint::Kind::Hinge &&
      !rotationKeptAbout(scene_, tree_, jt.body1, jt.body2, jt.axis)) {
    ball(jt.anchor + kSecondBallOffset * jt.axis.normalized());
  }
}

/// Body i's mobilizer speeds u from the scene's velocities: the spatial velocity of its M frame
/// (the child's point at the anchor) relative to F (the parent's), expressed in F.
void SimbodyEngine::fitVelocity(int i, SimTK::State& state) const {
  const auto ii = static_cast<std::size_t>(i);
  const Body& b = scene_.bodies[ii];
  const SimTK::MobilizedBody& mobod = matter_.getMobilizedBody(mobod_[ii]);
  const Quat to_f = frame_[ii].conjugate();
  if (tree_.free_root[ii]) {
    mobod.setUToFitVelocity(
        state, SimTK::SpatialVec(toSimTK(to_f * b.angular_velocity), toSimTK(to_f * b.velocity)));
    return;
  }
  const Joint& jt = scene_.joints[static_cast<std::size_t>(tree_.joint[ii])];
  const Body* parent = bodyOf(tree_.parent[ii]);
  const Vec3 w_FM =
      to_f * (b.angular_velocity - (parent ? parent->angular_velocity : Vec3::Zero()));
  const Vec3 v_FM = to_f * (pointVelocity(&b, jt.anchor) - pointVelocity(parent, jt.anchor));
  switch (jt.kind) {
    case Joint::Kind::Hinge:
    case Joint::Kind::Ball:
      mobod.setUToFitAngularVelocity(state, toSimTK(w_FM));
      return;
    case Joint::Kind::Slider:
      mobod.setUToFitLinearVelocity(state, toSimTK(v_FM));
      return;
    case Joint::Kind::Fixed:
      return;
  }
}

/// The bodies' velocities after the fit and projection against the scene's: a mismatch would be a
/// mapping error (or initial velocities that violate the loops), not Simbody's.
void SimbodyEngine::checkVelocities(const SimTK::State& state) const {
  double worst = 0.0;
  for (std::size_t i = 0; i < scene_.bodies.size(); ++i) {
    const SimTK::MobilizedBody& mobod = matter_.getMobilizedBody(mobod_[i]);
    const Body& b = scene_.bodies[i];
    worst =
        std::max({worst, (fromSimTK(mobod.getBodyOriginVelocity(state)) - b.velocity).norm(),
                  (fromSimTK(mobod.getBodyAngularVelocity(state)) - b.angular_velocity).norm()});
  }
  if (!(worst <= kVelocityFitTolerance)) {
    char why[200];
    std::snprintf(why, sizeof why,
                  "Simbody's initial velocities differ from the scene's by %.3g (m/s, rad/s)",
                  worst);
    throw std::runtime_error(why);
  }
}

void SimbodyEngine::startIntegrator(const Options& options, const SimTK::State& state) {
  if (options.method == Method::Merson) {
    integ_ = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system_);
  } else {
    integ_ = std::make_unique<SimTK::CPodesIntegrator>(system_, SimTK::CPodes::BDF,
                                                       SimTK::CPodes::Newton);
  }
  integ_->setAccuracy(options.accuracy);
  integ_->setConstraintTolerance(options.accuracy / 10);  // Simbody's default relationship
  integ_->setAllowInterpolation(false);                   // stepTo ends on a step
  integ_->setInternalStepLimit(kInternalStepLimit);
  integ_->initialize(state);
}

/// Integrates to the next multiple of the scene's timestep; stops on a non-finite state.
void SimbodyEngine::step() {
  ++steps_;
  if (diverged_) return;
  const double t = static_cast<double>(steps_) * h_;
  try {
    // CPodes can go on at steps of 1e-17 s without reaching its step limit: a stall too.
    double mark = integ_->getTime();
    for (int calls = 1; integ_->getTime() < t; ++calls) {
      advanceTowards(t);
      if (calls % kStallCalls != 0) continue;
      if (integ_->getTime() - mark < kStall * h_) {
        char why[200];
        std::snprintf(why, sizeof why,
                      "Simbody's integrator stalled at t = %.9g s: %d calls of stepTo advanced "
                      "less than %.3g s",
                      mark, kStallCalls, kStall * h_);
        throw std::runtime_error(why);
      }
      mark = integ_->getTime();
    }
  } catch (const std::exception& e) {
    if (!allFinite(integ_->getAdvancedState().getY())) {  // a blow-up, not a failure
      diverged_ = true;
      return;
    }
    if (dynamic_cast<const SimTK::Exception::Base*>(&e))
      throw std::runtime_error(oneLine(e.what()));
    throw;
  }
  if (!allFinite(integ_->getState().getY())) diverged_ = true;
}

/// One Integrator::stepTo(t). It returns early at the start (StartOfContinuousInterval) and, for
/// CPodes, after its internal step limit (ReachedStepLimit); a limit reached without progress is a
/// stall (CPodes goes on at steps of 1e-17 s where RK Merson throws), reported as a failure.
void SimbodyEngine::advanceTowards(double t) {
  const double before = integ_->getTime();
  const SimTK::Integrator::SuccessfulStepStatus status = integ_->stepTo(t);
  if (status == SimTK::Integrator::EndOfSimulation)
    throw std::runtime_error("Simbody's integrator ended the simulation");
  if (status == SimTK::Integrator::ReachedStepLimit && integ_->getTime() - before < kStall * h_) {
    char why[200];
    std::snprintf(why, sizeof why,
                  "Simbody's integrator stalled at t = %.9g s: it reached its internal step limit "
                  "having advanced less than %.3g s",
                  before, kStall * h_);
    throw std::runtime_error(why);
  }
}

Pose SimbodyEngine::pose(int i) const {
  if (diverged_) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return Pose{Vec3::Constant(nan), Quat(nan, nan, nan, nan)};
  }
  const SimTK::State& state = integ_->getState();
  const SimTK::MobilizedBody& mobod = matter_.getMobilizedBody(mobod_[static_cast<std::size_t>(i)]);
  const SimTK::Quaternion q = mobod.getBodyRotation(state).convertRotationToQuaternion();
  return Pose{fromSimTK(mobod.getBodyOriginLocation(state)), Quat(q[0], q[1], q[2], q[3])};
}

Twist SimbodyEngine::velocity(int i) const {
  if (diverged_) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return Twist{Vec3::Constant(nan), Vec3::Constant(nan)};
  }
  const SimTK::State& state = integ_->getState();
  const SimTK::MobilizedBody& mobod = matter_.getMobilizedBody(mobod_[static_cast<std::size_t>(i)]);
  return Twist{fromSimTK(mobod.getBodyOriginVelocity(state)),
               fromSimTK(mobod.getBodyAngularVelocity(state))};
}

std::string accuracyLabel(double accuracy) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%g", accuracy);
  return buf;
}

Variant variant(const Options& options) {
  const std::string acc = accuracyLabel(options.accuracy);
  const std::string tol = accuracyLabel(options.accuracy / 10);
  Variant v;
  v.engine = "Simbody";
  v.settings =
      (options.method == Method::Merson
           ? std::string("RungeKuttaMersonIntegrator (4th order, embedded error estimate)")
           : std::string("CPodesIntegrator (BDF, Newton iteration)")) +
      ", accuracy " + acc + ", constraint tolerance " + tol +
      " (accuracy / 10, Simbody's default), projection when the constraint error exceeds it; "
      "stepTo each step, no interpolation; loops: Constraint::Ball";
  v.make = [options](const Scene& scene) -> std::unique_ptr<Engine> {
    checkScene(scene);
    try {
      return std::make_unique<SimbodyEngine>(scene, options);
    } catch (const SimTK::Exception::Base& e) {
      throw std::runtime_error(oneLine(e.what()));
    }
  };
  v.knob = methodName(options.method) + ", accuracy " + acc;
  return v;
}

}  // namespace

std::vector<Variant> simbodyIntegrators(const Scene& /*scene*/) {
  std::vector<Variant> out;
  for (double accuracy : {1e-6, 1e-8, 1e-10})
    out.push_back(variant(Options{Method::Merson, accuracy}));
  out.push_back(variant(Options{Method::CPodesBdf, 1e-8}));
  return out;
}

}  // namespace bench
