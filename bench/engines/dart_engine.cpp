// DART 6.12 (Debian libdart-dev) adapter: one variant (the Pareto table adds PGS as the boxed-LCP
// solver at a given number of iterations), a dart::simulation::World with DART's default
// constraint solver, the BoxedLcpConstraintSolver (Dantzig's boxed LCP, dense per
// constrained group, PGS as the fallback when Dantzig fails), contact ERP / CFM / error allowance
// as DART sets them, semi-implicit Euler; and DART's own collision detector (DARTCollisionDetector:
// box-box, box-sphere and sphere-sphere tests; about 4 points per resting box pair, as in ODE)
// instead of its default, FCL. FCL as DART 6.12 drives it turns boxes into triangle meshes and
// collides them triangle by triangle: on the base-10 pyramid it made ~860 contact points (~16 per
// box) and 8.5 s per step with Dantzig, against ~400 points and 0.5 s with DART's own detector
// (measured on the 2-core test machine). Neither detector has capsules (FCL warns and collides a
// 0.1 m sphere instead), so scenes with capsules, the ragdolls, are refused; neither has a usable
// plane (FCL substitutes a zero-thickness box in the xz plane), so the ground is an immobile 1000 x
// 1000 x 2 m box whose top face is the plane.
//
// DART works in reduced (joint) coordinates (Featherstone's articulated bodies), so the scene
// becomes kinematic trees, one dart::dynamics::Skeleton per tree:
// - a breadth-first search from the world over the scene's joints makes the trees: a body's parent
//   is the body it was first reached from; a joint to the world or to a static body starts a
//   skeleton whose root joint is that joint (fixed base); a dynamic body reached by no joint is the
//   root of a skeleton of its own with a FreeJoint (floating base). Hinges are RevoluteJoints,
//   sliders PrismaticJoints, balls BallJoints, fixed joints WeldJoints, so every tree joint is
//   exact by construction. A joint that meets an already placed body closes a loop and becomes a
//   constraint of DART's solver instead: a ball a BallJointConstraint, a fixed joint a
//   WeldJointConstraint, a hinge a BallJointConstraint at its anchor when the trees already keep
//   the two bodies' relative rotation about the hinge axis (every joint between them a parallel
//   hinge or a slider, as in the planar slider-crank). DART 6.12 has no revolute or prismatic loop
//   constraint, so any other hinge closing a loop, a slider closing a loop, and limits or motors on
//   a loop-closing joint are refused (no scene has them).
// - every BodyNode frame is the scene body's principal frame (origin at the centre of mass), with
//   the scene's mass and principal inertia (never computed from the geometry), so pose() is the
//   BodyNode's world transform. A tree joint's frame sits at the scene's anchor with the world's
//   orientation at creation, so its axis is the scene's world axis; when the tree edge runs from
//   body2 to body1 the axis is negated (and the limits swapped and negated), so that DART's joint
//   coordinate is the scene's (body2 relative to body1).
// - hinge and slider limits are DART's position limits with limit enforcement on; a motor is a
//   SERVO actuator (DART's constraint motor: the solver tracks the commanded velocity within the
//   joint's force limits, +-max_force); the command is set again before every step, since
//   World::step resets commands.
// - shapes are ShapeNodes with collision and dynamics aspects (BoxShape, SphereShape), every one
//   with primary and secondary friction coefficients mu (DART combines a pair's coefficients, equal
//   here); restitution stays 0. Static bodies are immobile skeletons with a WeldJoint to the world.
// - collisions: a skeleton's bodies collide with each other except adjacent (parent-child) ones;
//   pairs joined by a loop-closing joint or by a joint to a static body are put on the blacklist of
//   a BodyNodeCollisionFilter. DART's world-wide cap on contact points per step (1,000 by default)
//   is raised to a per-shape budget (below), and a step that reaches it fails the run rather than
//   silently dropping contacts.
// - Dantzig's LCP is dense per constrained group (bodies linked by contacts, joints of a tree and
//   loop constraints) and its cost grows as the cube of the group's rows: groups estimated above
//   kDenseRowLimit rows are refused, as ODE's dWorldStep is.
#include "engine.hpp"
#include "scene_tree.hpp"

#include <dart/collision/CollisionFilter.hpp>
#include <dart/collision/CollisionResult.hpp>
#include <dart/collision/dart/DARTCollisionDetector.hpp>
#include <dart/constraint/BallJointConstraint.hpp>
#include <dart/constraint/BoxedLcpConstraintSolver.hpp>
#include <dart/constraint/BoxedLcpSolver.hpp>
#include <dart/constraint/ConstraintSolver.hpp>
#include <dart/constraint/ContactConstraint.hpp>
#include <dart/constraint/DynamicJointConstraint.hpp>
#include <dart/constraint/JointConstraint.hpp>
#include <dart/constraint/PgsBoxedLcpSolver.hpp>
#include <dart/constraint/WeldJointConstraint.hpp>
#include <dart/dynamics/BallJoint.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/BoxShape.hpp>
#include <dart/dynamics/CapsuleShape.hpp>
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/Inertia.hpp>
#include <dart/dynamics/PrismaticJoint.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/ShapeNode.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/SphereShape.hpp>
#include <dart/dynamics/WeldJoint.hpp>
#include <dart/simulation/World.hpp>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace bench {
namespace {

namespace dd = dart::dynamics;
namespace dc = dart::constraint;

// A joint coordinate (m, rad) or velocity (m/s, rad/s) beyond this is a blow-up.
constexpr double kDiverged = 1e8;
// The ground: a box, its top face the plane (DART 6.12's detectors have no usable plane).
constexpr double kGroundHalfWidth = 500.0, kGroundHalfThickness = 1.0;
// Contact points budgeted per dynamic body with a shape (DART's cap is world-wide): a box resting
// on two others holds up to 2 x 4, a sphere in a pile a few, a ragdoll capsule 2 at most.
constexpr std::size_t kContactsPerShapedBody = 16;
constexpr std::size_t kMinContacts = 1000;  // DART's default cap
// Dantzig's dense LCP: estimated rows of the largest constrained group above which the scene is
// refused (see checkDenseSize).
constexpr long kDenseRowLimit = 2000;
// PGS as the boxed-LCP solver (the Pareto table's sweep) works on the same dense matrix, built
// column by column (O(rows^2) per step, 8 rows^2 bytes), but never factors it: a larger limit,
// which lets in the 1,000-sphere pile (estimated 24,000 rows, far more than it has: measured
// 0.4 GB of peak memory and 0.2 to 0.3 s per step) and keeps out the 8,000 pile.
constexpr long kDensePgsRowLimit = 30000;
// Estimated contact rows per dynamic body with a shape, for that estimate: about two contact
// pairs of up to 4 points, 3 rows each (normal and two friction directions).
constexpr long kContactRowsPerShapedBody = 24;

Eigen::Isometry3d isometry(const Vec3& position, const Quat& orientation) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = orientation.normalized().toRotationMatrix();
  t.translation() = position;
  return t;
}

/// Checks what the adapter cannot build, before any DART object exists.
void checkFeatures(const Scene& scene, const SceneTree& tree) {
  if (!scene.springs.empty()) throw Unsupported("DART: the scene's springs are not mapped");
  for (const Body& b : scene.bodies) {
    if (b.shape.kind == Shape::Kind::Capsule) {
      throw Unsupported(
          "DART 6.12's collision detectors have no capsule (its own has none; FCL, its default, "
          "warns and collides a 0.1 m sphere instead)");
    }
  }
  for (int j : tree.closures) {
    const Joint& jt = scene.joints[static_cast<std::size_t>(j)];
    if (jt.limits || jt.motor) {
      throw Unsupported("DART: a limit or motor on a joint closing a loop is not modelled");
    }
    switch (jt.kind) {
      case Joint::Kind::Slider:
        throw Unsupported("DART 6.12 has no prismatic loop constraint (a slider closes a loop)");
      case Joint::Kind::Hinge:
        if (!rotationKeptAbout(scene, tree, treeNode(scene, jt.body1), treeNode(scene, jt.body2),
                               jt.axis)) {
          throw Unsupported(
              "DART 6.12 has no revolute loop constraint, and the trees do not keep the rotation "
              "about the axis of the hinge closing the loop");
        }
        break;
      case Joint::Kind::Ball:
      case Joint::Kind::Fixed:
        break;
    }
  }
  for (std::size_t j = 0; j < scene.joints.size(); ++j) {
    const Joint& jt = scene.joints[j];
    if ((jt.kind == Joint::Kind::Ball || jt.kind == Joint::Kind::Fixed) &&
        (jt.limits || jt.motor)) {
      throw Unsupported("DART: limits or motors on ball or fixed joints are not modelled");
    }
  }
}

/// Dantzig's LCP is dense per constrained group: estimates the rows of the largest one (bodies of
/// one tree or joined by a loop constraint; every dynamic body with a shape and no joint counted
/// in one pile, since they touch each other) and refuses the scene above `limit`.
void checkDenseSize(const Scene& scene, const SceneTree& tree, long limit, const char* solver) {
  const int n = static_cast<int>(scene.bodies.size());
  std::vector<int> up(static_cast<std::size_t>(n));
  std::iota(up.begin(), up.end(), 0);
  const auto find = [&up](int i) {
    while (up[static_cast<std::size_t>(i)] != i) {
      i = up[static_cast<std::size_t>(i)] =
          up[static_cast<std::size_t>(up[static_cast<std::size_t>(i)])];
    }
    return i;
  };
  const auto join = [&](int a, int b) {
    if (a >= 0 && b >= 0) up[static_cast<std::size_t>(find(a))] = find(b);
  };
  int pile = -1;
  for (int i = 0; i < n; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    const Body& b = scene.bodies[ui];
    if (b.is_static) continue;
    join(i, tree.parent[ui]);
    if (tree.free_root[ui] && tree.children[ui].empty() && b.shape.kind != Shape::Kind::None) {
      if (pile < 0) pile = i;
      join(i, pile);
    }
  }
  for (int j : tree.closures) {
    const Joint& jt = scene.joints[static_cast<std::size_t>(j)];
    join(treeNode(scene, jt.body1), treeNode(scene, jt.body2));
  }
  std::vector<long> rows(static_cast<std::size_t>(n), 0);
  for (int i = 0; i < n; ++i) {
    const Body& b = scene.bodies[static_cast<std::size_t>(i)];
    if (!b.is_static && b.shape.kind != Shape::Kind::None) {
      rows[static_cast<std::size_t>(find(i))] += kContactRowsPerShapedBody;
    }
  }
  for (const Joint& jt : scene.joints) {
    const int a =
        treeNode(scene, jt.body1) == kWorld ? treeNode(scene, jt.body2) : treeNode(scene, jt.body1);
    if (a != kWorld) rows[static_cast<std::size_t>(find(a))] += (jt.limits || jt.motor) ? 1 : 0;
  }
  for (int j : tree.closures) {
    const Joint& jt = scene.joints[static_cast<std::size_t>(j)];
    const int a =
        treeNode(scene, jt.body1) == kWorld ? treeNode(scene, jt.body2) : treeNode(scene, jt.body1);
    if (a != kWorld)
      rows[static_cast<std::size_t>(find(a))] += jt.kind == Joint::Kind::Fixed ? 6 : 3;
  }
  const long largest = n ? *std::max_element(rows.begin(), rows.end()) : 0;
  if (largest > limit) {
    throw Unsupported("DART's " + std::string(solver) +
                      " boxed LCP is dense per constrained group: ~" + std::to_string(largest) +
                      " constraint rows estimated, limit " + std::to_string(limit));
  }
}

/// A joint and its child body, named after the scene body (DART renames duplicates, and says so
/// on stdout).
template <class JointType>
std::pair<JointType*, dd::BodyNode*> addLink(const dd::SkeletonPtr& skel, dd::BodyNode* parent,
                                             int body) {
  typename JointType::Properties joint;
  joint.mName = "j" + std::to_string(body);
  dd::BodyNode::AspectProperties node;
  node.mName = "b" + std::to_string(body);
  return skel->createJointAndBodyNodePair<JointType>(parent, joint, node);
}

std::shared_ptr<dd::Shape> makeShape(const Shape& s) {
  switch (s.kind) {
    case Shape::Kind::None:
      return nullptr;
    case Shape::Kind::Sphere:
      return std::make_shared<dd::SphereShape>(s.radius);
    case Shape::Kind::Box:
      return std::make_shared<dd::BoxShape>(Eigen::Vector3d(2.0 * s.half_extents));
    case Shape::Kind::Capsule:  // refused by checkFeatures; height: between the sphere centres
      return std::make_shared<dd::CapsuleShape>(s.radius, 2.0 * s.half_length);
  }
  return nullptr;
}

class DartEngine final : public Engine {
 public:
  /// pgs_iterations > 0: PGS as the boxed-LCP solver at that many iterations (no fallback);
  /// otherwise DART's default, Dantzig with PGS as its fallback.
  DartEngine(const Scene& scene, int pgs_iterations);
  ~DartEngine() override = default;
  DartEngine(const DartEngine&) = delete;
  DartEngine& operator=(const DartEngine&) = delete;

  void step() override {
    for (const Motor& m : motors_) m.joint->setCommand(0, m.velocity);
    world_->step();
    // DART does not stop on a blow-up, and once a coordinate overflows, the next update of its
    // joint transform fails an assertion that aborts the process: a skeleton whose coordinates or
    // velocities leave kDiverged (or stop being finite) fails the run here, with the time.
    for (const dd::SkeletonPtr& skel : skeletons_) {
      if (skel->getNumDofs() == 0) continue;
      const Eigen::VectorXd q = skel->getPositions(), v = skel->getVelocities();
      if (!(q.cwiseAbs().maxCoeff() < kDiverged) || !(v.cwiseAbs().maxCoeff() < kDiverged)) {
        char why[160];
        std::snprintf(why, sizeof why,
                      "DART diverged at t = %.3f s (a joint coordinate or velocity beyond %g)",
                      world_->getTime(), kDiverged);
        throw std::runtime_error(why);
      }
    }
    const std::size_t contacts = world_->getLastCollisionResult().getNumContacts();
    if (contacts >= max_contacts_) {
      throw std::runtime_error("DART reached its cap of " + std::to_string(max_contacts_) +
                               " contact points at t = " + std::to_string(world_->getTime()) +
                               " s (it would drop the rest)");
    }
  }

  Pose pose(int i) const override {
    const dd::BodyNode* b = nodes_[static_cast<std::size_t>(i)];
    if (!b) return fixed_[static_cast<std::size_t>(i)];
    const Eigen::Isometry3d& t = b->getWorldTransform();
    return Pose{t.translation(), Quat(t.linear())};
  }

  // Both in the world frame (the defaults of their frame arguments); the BodyNode frame's origin
  // is the centre of mass, and getCOMLinearVelocity() says so whatever the frame.
  Twist velocity(int i) const override {
    const dd::BodyNode* b = nodes_[static_cast<std::size_t>(i)];
    if (!b) return Twist{};
    return Twist{b->getCOMLinearVelocity(), b->getAngularVelocity()};
  }

  std::size_t contactCount() const override {
    return world_->getLastCollisionResult().getNumContacts();
  }

 private:
  struct Motor {
    dd::Joint* joint;
    double velocity;
  };

  void addShape(dd::BodyNode* b, const Shape& shape, double mu) {
    std::shared_ptr<dd::Shape> s = makeShape(shape);
    if (!s) return;
    dd::ShapeNode* sn =
        b->createShapeNodeWith<dd::CollisionAspect, dd::DynamicsAspect>(std::move(s));
    sn->getDynamicsAspect()->setFrictionCoeff(mu);
    sn->getDynamicsAspect()->setPrimaryFrictionCoeff(mu);
    sn->getDynamicsAspect()->setSecondaryFrictionCoeff(mu);
  }

  std::shared_ptr<dart::simulation::World> world_;
  std::vector<dd::BodyNode*> nodes_;  // per scene body; nullptr for a static body without shape
  std::vector<Pose> fixed_;           // poses of static bodies
  std::vector<Motor> motors_;
  std::vector<dd::SkeletonPtr> skeletons_;  // the mobile ones
  std::size_t max_contacts_ = kMinContacts;
};

DartEngine::DartEngine(const Scene& scene, int pgs_iterations) {
  const SceneTree tree = buildSceneTree(scene, false);
  checkFeatures(scene, tree);
  if (pgs_iterations > 0) {
    checkDenseSize(scene, tree, kDensePgsRowLimit, "PGS");
  } else {
    checkDenseSize(scene, tree, kDenseRowLimit, "Dantzig");
  }

  const int n = static_cast<int>(scene.bodies.size());
  const auto un = static_cast<std::size_t>(n);
  nodes_.assign(un, nullptr);
  fixed_.resize(un);
  const double mu = scene.friction;

  world_ = dart::simulation::World::create("bench");
  world_->setGravity(scene.gravity);
  world_->setTimeStep(scene.timestep);
  dc::ConstraintSolver* solver = world_->getConstraintSolver();
  if (pgs_iterations > 0) {
    auto* boxed = dynamic_cast<dc::BoxedLcpConstraintSolver*>(solver);
    if (!boxed) throw std::runtime_error("DART's constraint solver is not a boxed-LCP one");
    auto pgs = std::make_shared<dc::PgsBoxedLcpSolver>();
    dc::PgsBoxedLcpSolver::Option option = pgs->getOption();
    option.mMaxIteration = pgs_iterations;
    pgs->setOption(option);
    boxed->setBoxedLcpSolver(pgs);
    boxed->setSecondaryBoxedLcpSolver(nullptr);
  }
  // DART's own detector rather than its default, FCL (see the top of this file).
  solver->setCollisionDetector(dart::collision::DARTCollisionDetector::create());
  auto filter = std::make_shared<dart::collision::BodyNodeCollisionFilter>();
  std::size_t shaped = 0;
  for (const Body& b : scene.bodies) {
    if (!b.is_static && b.shape.kind != Shape::Kind::None) ++shaped;
  }
  max_contacts_ = std::max(kMinContacts, kContactsPerShapedBody * shaped);
  solver->getCollisionOption().maxNumContacts = max_contacts_;
  solver->getCollisionOption().collisionFilter = filter;

  // Static bodies: immobile skeletons welded to the world.
  for (int i = 0; i < n; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    const Body& b = scene.bodies[ui];
    if (!b.is_static) continue;
    fixed_[ui] = Pose{b.position, b.orientation.normalized()};
    if (b.shape.kind == Shape::Kind::None) continue;
    dd::SkeletonPtr skel = dd::Skeleton::create("static" + std::to_string(i));
    auto [joint, body] = addLink<dd::WeldJoint>(skel, nullptr, i);
    joint->setTransformFromParentBodyNode(isometry(b.position, b.orientation));
    addShape(body, b.shape, mu);
    skel->setMobile(false);
    world_->addSkeleton(skel);
    nodes_[ui] = body;
  }
  if (scene.ground_z) {
    dd::SkeletonPtr skel = dd::Skeleton::create("ground");
    auto pair = skel->createJointAndBodyNodePair<dd::WeldJoint>();
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.translation() = Vec3(0.0, 0.0, *scene.ground_z - kGroundHalfThickness);
    pair.first->setTransformFromParentBodyNode(t);
    auto shape = std::make_shared<dd::BoxShape>(Eigen::Vector3d(
        2.0 * kGroundHalfWidth, 2.0 * kGroundHalfWidth, 2.0 * kGroundHalfThickness));
    dd::ShapeNode* sn =
        pair.second->createShapeNodeWith<dd::CollisionAspect, dd::DynamicsAspect>(shape);
    sn->getDynamicsAspect()->setFrictionCoeff(mu);
    sn->getDynamicsAspect()->setPrimaryFrictionCoeff(mu);
    sn->getDynamicsAspect()->setSecondaryFrictionCoeff(mu);
    skel->setMobile(false);
    world_->addSkeleton(skel);
  }

  // Dynamic bodies: one skeleton per tree, parents before children (breadth-first).
  const auto poseOf = [&](int v) {
    return v == kWorld ? Eigen::Isometry3d(Eigen::Isometry3d::Identity())
                       : isometry(scene.bodies[static_cast<std::size_t>(v)].position,
                                  scene.bodies[static_cast<std::size_t>(v)].orientation);
  };
  const auto velOf = [&](int v) {
    return v == kWorld ? Vec3(Vec3::Zero()) : scene.bodies[static_cast<std::size_t>(v)].velocity;
  };
  const auto omegaOf = [&](int v) {
    return v == kWorld ? Vec3(Vec3::Zero())
                       : scene.bodies[static_cast<std::size_t>(v)].angular_velocity;
  };
  struct Velocity {
    dd::Joint* joint;
    double value;
  };
  std::vector<Velocity> joint_velocities;
  std::vector<std::pair<dd::FreeJoint*, int>> free_joints;
  int skeletons = 0;
  for (int root : tree.roots) {
    dd::SkeletonPtr skel = dd::Skeleton::create("tree" + std::to_string(skeletons++));
    std::vector<int> order{root};
    for (std::size_t k = 0; k < order.size(); ++k) {
      for (int c : tree.children[static_cast<std::size_t>(order[k])]) order.push_back(c);
    }
    for (int v : order) {
      const auto vi = static_cast<std::size_t>(v);
      const Body& b = scene.bodies[vi];
      const int p = tree.parent[vi];
      dd::BodyNode* parent = p == kWorld ? nullptr : nodes_[static_cast<std::size_t>(p)];
      dd::BodyNode* body = nullptr;
      dd::Joint* joint = nullptr;
      if (tree.free_root[vi]) {
        auto pair = addLink<dd::FreeJoint>(skel, parent, v);
        body = pair.second;
        free_joints.emplace_back(pair.first, v);
        pair.first->setPositions(dd::FreeJoint::convertToPositions(poseOf(v)));
      } else {
        const Joint& jt = scene.joints[static_cast<std::size_t>(tree.joint[vi])];
        const Vec3 axis = (tree.flipped[vi] ? Vec3(-jt.axis) : jt.axis).normalized();
        // The joint frame: at the anchor, with the world's orientation (at creation).
        Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
        frame.translation() = jt.anchor;
        switch (jt.kind) {
          case Joint::Kind::Hinge: {
            auto pair = addLink<dd::RevoluteJoint>(skel, parent, v);
            pair.first->setAxis(axis);
            joint = pair.first;
            body = pair.second;
            joint_velocities.push_back({joint, (b.angular_velocity - omegaOf(p)).dot(axis)});
            break;
          }
          case Joint::Kind::Slider: {
            auto pair = addLink<dd::PrismaticJoint>(skel, parent, v);
            pair.first->setAxis(axis);
            joint = pair.first;
            body = pair.second;
            const Vec3 pv = velOf(p) + omegaOf(p).cross(b.position - poseOf(p).translation());
            joint_velocities.push_back({joint, (b.velocity - pv).dot(axis)});
            break;
          }
          case Joint::Kind::Ball: {
            auto pair = addLink<dd::BallJoint>(skel, parent, v);
            joint = pair.first;
            body = pair.second;
            break;
          }
          case Joint::Kind::Fixed: {
            auto pair = addLink<dd::WeldJoint>(skel, parent, v);
            joint = pair.first;
            body = pair.second;
            break;
          }
        }
        joint->setTransformFromParentBodyNode(poseOf(p).inverse() * frame);
        joint->setTransformFromChildBodyNode(poseOf(v).inverse() * frame);
        if (jt.limits) {
          const double lo = tree.flipped[vi] ? -jt.limits->upper : jt.limits->lower;
          const double hi = tree.flipped[vi] ? -jt.limits->lower : jt.limits->upper;
          joint->setPositionLowerLimit(0, lo);
          joint->setPositionUpperLimit(0, hi);
          joint->setLimitEnforcement(true);
        }
        if (jt.motor) {
          joint->setActuatorType(dd::Joint::SERVO);
          joint->setForceLowerLimit(0, -jt.motor->max_force);
          joint->setForceUpperLimit(0, jt.motor->max_force);
          const double target =
              tree.flipped[vi] ? -jt.motor->target_velocity : jt.motor->target_velocity;
          motors_.push_back({joint, target});
        }
      }
      body->setInertia(
          dd::Inertia(b.mass, Eigen::Vector3d::Zero(), Eigen::Matrix3d(b.inertia.asDiagonal())));
      addShape(body, b.shape, mu);
      nodes_[vi] = body;
    }
    // Bodies of one tree collide with each other, except a parent and its child.
    skel->setSelfCollisionCheck(true);
    skel->setAdjacentBodyCheck(false);
    world_->addSkeleton(skel);
    skeletons_.push_back(skel);
  }

  // Initial velocities (after every skeleton has its pose).
  for (const Velocity& v : joint_velocities) v.joint->setVelocity(0, v.value);
  for (const auto& [joint, v] : free_joints) {
    const Body& b = scene.bodies[static_cast<std::size_t>(v)];
    joint->setLinearVelocity(b.velocity);
    joint->setAngularVelocity(b.angular_velocity);
  }

  // Loop closures, and the pairs that must not collide.
  const auto nodeOf = [&](int b) { return b < 0 ? nullptr : nodes_[static_cast<std::size_t>(b)]; };
  for (int j : tree.closures) {
    const Joint& jt = scene.joints[static_cast<std::size_t>(j)];
    dd::BodyNode* b1 = treeNode(scene, jt.body1) == kWorld ? nullptr : nodeOf(jt.body1);
    dd::BodyNode* b2 = treeNode(scene, jt.body2) == kWorld ? nullptr : nodeOf(jt.body2);
    if (!b1) std::swap(b1, b2);
    std::shared_ptr<dc::ConstraintBase> c;
    if (jt.kind == Joint::Kind::Fixed) {
      c = b2 ? std::make_shared<dc::WeldJointConstraint>(b1, b2)
             : std::make_shared<dc::WeldJointConstraint>(b1);
    } else {  // a ball, or a hinge whose rotation the trees keep (checkFeatures)
      c = b2 ? std::make_shared<dc::BallJointConstraint>(b1, b2, jt.anchor)
             : std::make_shared<dc::BallJointConstraint>(b1, jt.anchor);
    }
    solver->addConstraint(c);
  }
  for (std::size_t j = 0; j < scene.joints.size(); ++j) {
    const Joint& jt = scene.joints[j];
    dd::BodyNode* a = nodeOf(jt.body1);
    dd::BodyNode* b = nodeOf(jt.body2);
    const bool closure =
        std::binary_search(tree.closures.begin(), tree.closures.end(), static_cast<int>(j));
    const bool to_static =
        (jt.body1 >= 0 && scene.bodies[static_cast<std::size_t>(jt.body1)].is_static) ||
        (jt.body2 >= 0 && scene.bodies[static_cast<std::size_t>(jt.body2)].is_static);
    if ((closure || to_static) && a && b) filter->addBodyNodePairToBlackList(a, b);
  }
}

std::string settingsString(int pgs_iterations) {
  auto world = dart::simulation::World::create("settings");
  const dc::ConstraintSolver* solver = world->getConstraintSolver();
  std::string lcp = "?", fallback = "none";
  if (const auto* boxed = dynamic_cast<const dc::BoxedLcpConstraintSolver*>(solver)) {
    if (boxed->getBoxedLcpSolver()) lcp = boxed->getBoxedLcpSolver()->getType();
    if (boxed->getSecondaryBoxedLcpSolver()) {
      fallback = boxed->getSecondaryBoxedLcpSolver()->getType();
    }
  }
  if (pgs_iterations > 0) {
    lcp = dc::PgsBoxedLcpSolver::getStaticType();
    lcp += ' ';
    lcp += std::to_string(pgs_iterations);
    lcp += " it";
    fallback = "none";
  }
  const std::string detector = dart::collision::DARTCollisionDetector::getStaticType();
  char buf[500];
  std::snprintf(
      buf, sizeof buf,
      "BoxedLcpConstraintSolver: %s, fallback %s; %s collision; contact ERP %g, CFM %g, max "
      "ERV %g, allowance %g; joint ERP %g, CFM %g; loops ERP %g, CFM %g; 2 friction "
      "dirs; motor: SERVO",
      lcp.c_str(), fallback.c_str(), detector.c_str(),
      dc::ContactConstraint::getErrorReductionParameter(),
      dc::ContactConstraint::getConstraintForceMixing(),
      dc::ContactConstraint::getMaxErrorReductionVelocity(),
      dc::ContactConstraint::getErrorAllowance(), dc::JointConstraint::getErrorReductionParameter(),
      dc::JointConstraint::getConstraintForceMixing(),
      dc::DynamicJointConstraint::getErrorReductionParameter(),
      dc::DynamicJointConstraint::getConstraintForceMixing());
  return buf;
}

Variant variant(int pgs_iterations, std::string knob) {
  Variant v;
  v.engine = "DART";
  v.settings = settingsString(pgs_iterations);
  v.make = [pgs_iterations](const Scene& scene) -> std::unique_ptr<Engine> {
    return std::make_unique<DartEngine>(scene, pgs_iterations);
  };
  v.knob = std::move(knob);
  return v;
}

}  // namespace

std::vector<Variant> dartVariants(const Scene&) {
  return {variant(0, "default: Dantzig, PGS fallback")};
}

std::vector<Variant> dartSweep(const Scene& /*scene*/, const std::vector<int>& counts) {
  std::vector<Variant> out{variant(0, "default: Dantzig (no count), PGS fallback")};
  for (int iterations : counts) {
    std::string knob("PGS, PgsBoxedLcpSolver::Option::mMaxIteration = ");
    knob += std::to_string(iterations);
    out.push_back(variant(iterations, std::move(knob)));
  }
  return out;
}

}  // namespace bench
