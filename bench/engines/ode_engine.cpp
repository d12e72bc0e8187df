// ODE 0.16 (Debian libode-dev, double precision) adapter: dWorldQuickStep (projected Gauss-Seidel,
// 20 iterations; 10 to 100 in the Pareto table) and dWorldStep (the direct "big matrix" Dantzig
// LCP, dense per island).
//
// Mapping of the scene:
// - a dynamic body is a dBody with the scene's mass and principal inertia (dMassSetParameters,
//   never recomputed from the geometry), pose and velocities; its shape is a geom attached to it
//   (ODE's capsule lies along its local z, like the scene's);
// - a static body is a geom without a body (it never moves); a static body without a shape is
//   only remembered, for pose();
// - the ground is a dPlane;
// - joints: ODE measures a hinge angle / slider position (and drives its motor) as body1 relative
//   to body2, the scene as body2 relative to body1, so every joint is attached in swapped order
//   (when that would put the world first, the body stays first and the axis is flipped); an end
//   that is the world or a static body is ODE's static environment (0);
// - contacts: one sweep-and-prune space; the near callback skips pairs joined by a joint
//   (dAreConnectedExcluding, plus a list for joints to static bodies), asks for at most 4 points
//   per pair and makes hard contacts (the world's ERP and CFM, no bounce, no softness) with
//   Coulomb friction mu = scene friction in ODE's pyramid approximation (dContactApprox1: two
//   fixed tangent directions, each bounded by mu times the normal force); the contact group is
//   emptied after every step.
// Everything else is left at ODE's defaults (ERP 0.2, CFM 1e-10 in double precision, SOR 1.3,
// contact surface layer 0, no max correcting velocity, no damping, no auto-disable). ODE's global
// random generator (QuickStep reorders constraints with it) is reseeded by every new engine, so a
// run is reproducible as long as one ODE engine steps at a time.
#include "engine.hpp"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

namespace bench {
namespace {

constexpr int kQuickStepIterations = 20;
constexpr int kMaxContactsPerPair = 4;
// dWorldStep builds and factors a dense m x m LCP per island, O(m^3) or worse once the matrix
// leaves the cache: measured on the 2-core test machine, a 100-link chain (500 rows) takes ~12 ms
// per step, 200 links (1,000 rows) ~0.4 s, 400 links ~2.9 s; a base-10 pyramid (~1,300 contact
// rows) ~0.5 s. Islands estimated above this limit are refused.
constexpr int kDenseRowLimit = 1000;
// Estimated contact rows per body with a shape, for that estimate: a resting box has about two
// contact pairs (with the bodies below it, or the ground) of up to 4 points and 3 rows each.
constexpr int kContactRowsPerShapedBody = 24;

/// dInitODE2 once per process (reference counted by ODE), dCloseODE at exit.
struct OdeLibrary {
  OdeLibrary() {
    if (dInitODE2(0) == 0) throw Unsupported("dInitODE2 failed");
    if (dAllocateODEDataForThread(dAllocateMaskAll) == 0) {
      dCloseODE();
      throw Unsupported("dAllocateODEDataForThread failed");
    }
  }
  ~OdeLibrary() { dCloseODE(); }
  OdeLibrary(const OdeLibrary&) = delete;
  OdeLibrary& operator=(const OdeLibrary&) = delete;
};

void ensureOde() {
  static OdeLibrary library;
}

std::string commonSettings() {
  return "ERP 0.2, CFM 1e-10, hard contacts, pyramid friction (Approx1), " +
         std::to_string(kMaxContactsPerPair) + " pts/pair";
}

/// Constraint rows an ODE joint adds (a limit or motor adds one row, shared by both).
int jointRows(const Joint& j) {
  const int extra = (j.limits || j.motor) ? 1 : 0;
  switch (j.kind) {
    case Joint::Kind::Hinge:
      return 5 + extra;
    case Joint::Kind::Slider:
      return 5 + extra;
    case Joint::Kind::Ball:
      return 3;
    case Joint::Kind::Fixed:
      return 6;
  }
  return 6;
}

bool isDynamic(const Scene& s, int i) {
  return i >= 0 && i < static_cast<int>(s.bodies.size()) && !s.bodies[i].is_static;
}

/// Throws Unsupported for what this adapter does not model.
void checkFeatures(const Scene& s) {
  const int n = static_cast<int>(s.bodies.size());
  for (const Joint& j : s.joints) {
    if (j.body1 < -1 || j.body1 >= n || j.body2 < -1 || j.body2 >= n) {
      throw Unsupported("joint refers to a body that does not exist");
    }
    if ((j.kind == Joint::Kind::Ball || j.kind == Joint::Kind::Fixed) && (j.limits || j.motor)) {
      throw Unsupported("limits or motors on ball/fixed joints are not modelled");
    }
  }
}

/// dWorldStep: estimates the constraint rows of the largest island (joint-connected bodies; all
/// bodies with a shape and no joint counted as one pile, since they touch each other) and refuses
/// the scene above kDenseRowLimit.
void checkDenseSize(const Scene& s) {
  const int n = static_cast<int>(s.bodies.size());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&parent](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::vector<char> jointed(n, 0);
  for (const Joint& j : s.joints) {
    const bool d1 = isDynamic(s, j.body1), d2 = isDynamic(s, j.body2);
    if (d1) jointed[j.body1] = 1;
    if (d2) jointed[j.body2] = 1;
    if (d1 && d2) parent[find(j.body1)] = find(j.body2);
  }
  int pile = -1;  // free bodies with shapes share one island
  for (int i = 0; i < n; ++i) {
    const Body& b = s.bodies[i];
    if (b.is_static || jointed[i] || b.shape.kind == Shape::Kind::None) continue;
    if (pile < 0) {
      pile = i;
    } else {
      parent[find(i)] = find(pile);
    }
  }
  std::vector<long> rows(n, 0);
  for (int i = 0; i < n; ++i) {
    if (!s.bodies[i].is_static && s.bodies[i].shape.kind != Shape::Kind::None) {
      rows[find(i)] += kContactRowsPerShapedBody;
    }
  }
  for (const Joint& j : s.joints) {
    const int a = isDynamic(s, j.body1) ? j.body1 : j.body2;
    if (isDynamic(s, a)) rows[find(a)] += jointRows(j);
  }
  const long largest = n ? *std::max_element(rows.begin(), rows.end()) : 0;
  if (largest > kDenseRowLimit) {
    throw Unsupported("dWorldStep is a dense O(m^3) LCP per island: ~" + std::to_string(largest) +
                      " constraint rows estimated, limit " + std::to_string(kDenseRowLimit));
  }
}

/// A body rate (m/s or rad/s) no scene reaches: past it a run has blown up.
constexpr double kBlownUpSpeed = 1e6;

class OdeEngine final : public Engine {
 public:
  /// quick: dWorldQuickStep at `iterations`; otherwise dWorldStep. Each step() is `substeps`
  /// ODE steps of scene.timestep / substeps.
  OdeEngine(const Scene& scene, bool quick, int iterations, int substeps = 1);
  ~OdeEngine() override;
  OdeEngine(const OdeEngine&) = delete;
  OdeEngine& operator=(const OdeEngine&) = delete;

  void step() override;
  Pose pose(int i) const override;
  Twist velocity(int i) const override;

 private:
  static void nearCallback(void* data, dGeomID a, dGeomID b);
  void collide(dGeomID a, dGeomID b);

  bool quick_;
  int substeps_;
  double h_;
  double mu_;
  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  dJointGroupID contacts_ = nullptr;
  std::vector<dBodyID> bodies_;                // per scene body; nullptr for static bodies
  std::vector<Pose> fixed_;                    // poses of static bodies
  std::vector<int> index_;                     // geom data: the scene body index
  std::vector<std::pair<int, int>> excluded_;  // (static, dynamic) pairs joined by a joint, sorted
  /// The scene's springs, each end in its body's frame (the world's for the world, or a static
  /// body's end, held at its world point): ODE has none, so step() applies their forces.
  struct SpringEnd {
    dBodyID body = nullptr;
    Vec3 point = Vec3::Zero();
  };
  struct OdeSpring {
    SpringEnd a, b;
    double stiffness = 0.0, damping = 0.0, rest = 0.0;
  };
  std::vector<OdeSpring> springs_;
  void applySprings();
  /// Whether a body's rate passed kBlownUpSpeed (or is not finite).
  bool blownUp() const;
  bool diverged_ = false;
};

OdeEngine::OdeEngine(const Scene& scene, bool quick, int iterations, int substeps)
    : quick_(quick), substeps_(substeps), h_(scene.timestep / substeps), mu_(scene.friction) {
  const int n = static_cast<int>(scene.bodies.size());
  // Every C++ allocation happens before the first ODE object exists, so nothing can leak if one
  // throws.
  bodies_.assign(n, nullptr);
  fixed_.resize(n);
  index_.resize(n);
  std::iota(index_.begin(), index_.end(), 0);
  excluded_.reserve(2 * scene.joints.size());
  springs_.reserve(scene.springs.size());
  // QuickStep reorders its constraints with ODE's global generator every 8 iterations: restart it,
  // so that a run does not depend on what ran before it in the process.
  dRandSetSeed(0);
  world_ = dWorldCreate();
  // Sweep and prune: 2-3x cheaper than dHashSpace on these scenes (measured), same contacts.
  space_ = dSweepAndPruneSpaceCreate(nullptr, dSAP_AXES_XYZ);
  contacts_ = dJointGroupCreate(0);
  dWorldSetGravity(world_, scene.gravity.x(), scene.gravity.y(), scene.gravity.z());
  dWorldSetQuickStepNumIterations(world_, iterations);

  for (int i = 0; i < n; ++i) {
    const Body& b = scene.bodies[i];
    const dQuaternion q = {b.orientation.w(), b.orientation.x(), b.orientation.y(),
                           b.orientation.z()};
    dGeomID g = nullptr;
    switch (b.shape.kind) {
      case Shape::Kind::None:
        break;
      case Shape::Kind::Sphere:
        g = dCreateSphere(space_, b.shape.radius);
        break;
      case Shape::Kind::Box:
        g = dCreateBox(space_, 2 * b.shape.half_extents.x(), 2 * b.shape.half_extents.y(),
                       2 * b.shape.half_extents.z());
        break;
      case Shape::Kind::Capsule:
        g = dCreateCapsule(space_, b.shape.radius, 2 * b.shape.half_length);
        break;
    }
    if (g) dGeomSetData(g, &index_[i]);
    if (b.is_static) {
      fixed_[i] = Pose{b.position, b.orientation};
      if (g) {
        dGeomSetPosition(g, b.position.x(), b.position.y(), b.position.z());
        dGeomSetQuaternion(g, q);
      }
      continue;
    }
    dBodyID body = dBodyCreate(world_);
    dMass m;
    dMassSetParameters(&m, b.mass, 0, 0, 0, b.inertia.x(), b.inertia.y(), b.inertia.z(), 0, 0, 0);
    dBodySetMass(body, &m);
    dBodySetPosition(body, b.position.x(), b.position.y(), b.position.z());
    dBodySetQuaternion(body, q);
    dBodySetLinearVel(body, b.velocity.x(), b.velocity.y(), b.velocity.z());
    dBodySetAngularVel(body, b.angular_velocity.x(), b.angular_velocity.y(),
                       b.angular_velocity.z());
    if (g) dGeomSetBody(g, body);
    bodies_[i] = body;
  }
  for (const Spring& sp : scene.springs) {
    const auto end = [&](int i, const Vec3& point) {
      SpringEnd e;
      e.body = i >= 0 ? bodies_[static_cast<std::size_t>(i)] : nullptr;
      e.point = point;
      if (e.body) {
        dVector3 local;
        dBodyGetPosRelPoint(e.body, point.x(), point.y(), point.z(), local);
        e.point = Vec3(local[0], local[1], local[2]);
      }
      return e;
    };
    springs_.push_back(
        {end(sp.body1, sp.anchor1), end(sp.body2, sp.anchor2), sp.stiffness, sp.damping, sp.rest});
  }
  if (scene.ground_z) {
    dGeomID plane = dCreatePlane(space_, 0, 0, 1, *scene.ground_z);
    dGeomSetData(plane, nullptr);
  }

  const auto bodyOf = [this](int i) { return i >= 0 ? bodies_[i] : nullptr; };
  for (const Joint& j : scene.joints) {
    // Swapped: ODE's coordinate is body1 relative to body2, the scene's body2 relative to body1.
    dBodyID o1 = bodyOf(j.body2), o2 = bodyOf(j.body1);
    if (!o1 && !o2) continue;  // both ends fixed: nothing to constrain
    Vec3 x = j.axis;
    if (!o1) {
      // ODE would swap the bodies itself and flag the joint reversed, but 0.16's hinge limits and
      // motor ignore that flag. Keep the body first and flip the axis instead: the rotation of
      // body1 relative to the world about -axis is that of the world relative to body1 about axis.
      std::swap(o1, o2);
      x = -x;
    }
    for (const auto& [s, d] : {std::pair{j.body1, j.body2}, std::pair{j.body2, j.body1}}) {
      if (s >= 0 && scene.bodies[s].is_static && d >= 0 && !scene.bodies[d].is_static) {
        excluded_.emplace_back(s, d);
      }
    }
    const Vec3& a = j.anchor;
    dJointID joint = nullptr;
    switch (j.kind) {
      case Joint::Kind::Hinge:
        joint = dJointCreateHinge(world_, nullptr);
        dJointAttach(joint, o1, o2);
        dJointSetHingeAnchor(joint, a.x(), a.y(), a.z());
        dJointSetHingeAxis(joint, x.x(), x.y(), x.z());
        if (j.limits) {
          dJointSetHingeParam(joint, dParamLoStop, j.limits->lower);
          dJointSetHingeParam(joint, dParamHiStop, j.limits->upper);
        }
        if (j.motor) {
          dJointSetHingeParam(joint, dParamVel, j.motor->target_velocity);
          dJointSetHingeParam(joint, dParamFMax, j.motor->max_force);
        }
        break;
      case Joint::Kind::Slider:
        joint = dJointCreateSlider(world_, nullptr);
        dJointAttach(joint, o1, o2);
        dJointSetSliderAxis(joint, x.x(), x.y(), x.z());
        if (j.limits) {
          dJointSetSliderParam(joint, dParamLoStop, j.limits->lower);
          dJointSetSliderParam(joint, dParamHiStop, j.limits->upper);
        }
        if (j.motor) {
          dJointSetSliderParam(joint, dParamVel, j.motor->target_velocity);
          dJointSetSliderParam(joint, dParamFMax, j.motor->max_force);
        }
        break;
      case Joint::Kind::Ball:
        joint = dJointCreateBall(world_, nullptr);
        dJointAttach(joint, o1, o2);
        dJointSetBallAnchor(joint, a.x(), a.y(), a.z());
        break;
      case Joint::Kind::Fixed:
        joint = dJointCreateFixed(world_, nullptr);
        dJointAttach(joint, o1, o2);
        dJointSetFixed(joint);
        break;
    }
  }
  std::sort(excluded_.begin(), excluded_.end());
}

OdeEngine::~OdeEngine() {
  dJointGroupDestroy(contacts_);
  dSpaceDestroy(space_);  // destroys its geoms (cleanup mode is on by default)
  dWorldDestroy(world_);  // destroys bodies and joints
}

void OdeEngine::nearCallback(void* data, dGeomID a, dGeomID b) {
  static_cast<OdeEngine*>(data)->collide(a, b);
}

void OdeEngine::collide(dGeomID a, dGeomID b) {
  dBodyID b1 = dGeomGetBody(a), b2 = dGeomGetBody(b);
  if (!b1 && !b2) return;  // static against static or the ground
  if (b1 && b2 && dAreConnectedExcluding(b1, b2, dJointTypeContact)) return;
  if (!excluded_.empty() && (!b1 || !b2)) {
    const void* da = dGeomGetData(a);
    const void* db = dGeomGetData(b);
    if (da && db) {
      const int ia = *static_cast<const int*>(da), ib = *static_cast<const int*>(db);
      const auto key = b1 ? std::pair{ib, ia} : std::pair{ia, ib};  // (static, dynamic)
      if (std::binary_search(excluded_.begin(), excluded_.end(), key)) return;
    }
  }
  dContact contact[kMaxContactsPerPair] = {};
  const int count = dCollide(a, b, kMaxContactsPerPair, &contact[0].geom, sizeof(dContact));
  for (int k = 0; k < count; ++k) {
    contact[k].surface.mode = dContactApprox1;
    contact[k].surface.mu = mu_;
    dJointID c = dJointCreateContact(world_, contacts_, &contact[k]);
    dJointAttach(c, b1, b2);
  }
}

/// Each spring's tension k (d - rest) + c d' at the bodies' state, at its two points (explicit,
/// as ODE's own forces are: held for the step).
void OdeEngine::applySprings() {
  const auto at = [](const SpringEnd& e, Vec3& x, Vec3& v) {
    if (!e.body) {
      x = e.point;
      v.setZero();
      return;
    }
    dVector3 p, u;
    dBodyGetRelPointPos(e.body, e.point.x(), e.point.y(), e.point.z(), p);
    dBodyGetRelPointVel(e.body, e.point.x(), e.point.y(), e.point.z(), u);
    x = Vec3(p[0], p[1], p[2]);
    v = Vec3(u[0], u[1], u[2]);
  };
  for (const OdeSpring& s : springs_) {
    Vec3 xa, va, xb, vb;
    at(s.a, xa, va);
    at(s.b, xb, vb);
    const Vec3 d = xb - xa;
    const double length = d.norm();
    if (!(length > 0.0)) continue;
    const Vec3 n = d / length;
    const Vec3 f = (s.stiffness * (length - s.rest) + s.damping * n.dot(vb - va)) * n;
    if (s.a.body) dBodyAddForceAtPos(s.a.body, f.x(), f.y(), f.z(), xa.x(), xa.y(), xa.z());
    if (s.b.body) dBodyAddForceAtPos(s.b.body, -f.x(), -f.y(), -f.z(), xb.x(), xb.y(), xb.z());
  }
}

bool OdeEngine::blownUp() const {
  for (const dBodyID b : bodies_) {
    if (!b) continue;
    const dReal* v = dBodyGetLinearVel(b);
    const dReal* w = dBodyGetAngularVel(b);
    for (int k = 0; k < 3; ++k)
      if (!(std::abs(v[k]) < kBlownUpSpeed && std::abs(w[k]) < kBlownUpSpeed)) return true;
  }
  return false;
}

void OdeEngine::step() {
  if (diverged_) return;
  for (int k = 0; k < substeps_; ++k) {
    // ODE aborts the process (an internal assertion) on a quaternion its growing rates have made
    // non-finite: a run that has blown up stops first, its poses NaN from then on.
    if (blownUp()) {
      diverged_ = true;
      return;
    }
    applySprings();
    dSpaceCollide(space_, this, &OdeEngine::nearCallback);
    if (quick_) {
      dWorldQuickStep(world_, h_);
    } else {
      dWorldStep(world_, h_);
    }
    dJointGroupEmpty(contacts_);
  }
}

Pose OdeEngine::pose(int i) const {
  const dBodyID b = bodies_.at(i);
  if (!b) return fixed_[i];
  if (diverged_) return Pose{Vec3::Constant(NAN), Quat(NAN, NAN, NAN, NAN)};
  const dReal* p = dBodyGetPosition(b);
  const dReal* q = dBodyGetQuaternion(b);
  return Pose{Vec3(p[0], p[1], p[2]), Quat(q[0], q[1], q[2], q[3])};
}

// The body's position is its centre of mass (dMassSetParameters with the centre at the origin),
// so dBodyGetLinearVel is the centre of mass's velocity; both are in the world frame.
Twist OdeEngine::velocity(int i) const {
  const dBodyID b = bodies_.at(i);
  if (!b) return Twist{};
  if (diverged_) return Twist{Vec3::Constant(NAN), Vec3::Constant(NAN)};
  const dReal* v = dBodyGetLinearVel(b);
  const dReal* w = dBodyGetAngularVel(b);
  return Twist{Vec3(v[0], v[1], v[2]), Vec3(w[0], w[1], w[2])};
}

Variant quickStep(int iterations) {
  Variant v{"ODE",
            "dWorldQuickStep " + std::to_string(iterations) + " it (SOR 1.3), " + commonSettings(),
            [iterations](const Scene& s) -> std::unique_ptr<Engine> {
              checkFeatures(s);
              ensureOde();
              return std::make_unique<OdeEngine>(s, true, iterations);
            },
            false};
  std::string knob("dWorldQuickStep, dWorldSetQuickStepNumIterations = ");
  knob += std::to_string(iterations);
  v.knob = std::move(knob);
  return v;
}

/// dWorldStep, each step() `substeps` of its steps (the main table's row: 1).
Variant directStep(int substeps) {
  std::string settings = "dWorldStep (dense LCP), " + commonSettings();
  std::string knob = "dWorldStep";
  if (substeps > 1) {
    settings +=
        ", " + std::to_string(substeps) + " substeps (h / " + std::to_string(substeps) + ")";
    knob += ", h / " + std::to_string(substeps);
  }
  Variant v{"ODE", std::move(settings),
            [substeps](const Scene& s) -> std::unique_ptr<Engine> {
              checkFeatures(s);
              checkDenseSize(s);
              ensureOde();
              return std::make_unique<OdeEngine>(s, false, 0, substeps);
            },
            false};
  v.knob = std::move(knob);
  return v;
}

}  // namespace

std::vector<Variant> odeVariants(const Scene& /*scene*/) {
  return {quickStep(kQuickStepIterations), directStep(1)};
}

// The integrator table: dWorldStep (ODE's most accurate) at h and at h / 16.
std::vector<Variant> odeIntegrators(const Scene& /*scene*/) {
  return {directStep(1), directStep(16)};
}

// ODE's default row is dWorldQuickStep, swept; dWorldStep has no count (and is refused by the
// pyramids and piles for its dense LCP).
std::vector<Variant> odeSweep(const Scene& /*scene*/, const std::vector<int>& counts) {
  std::vector<Variant> v;
  for (int iterations : counts) v.push_back(quickStep(iterations));
  return v;
}

}  // namespace bench
